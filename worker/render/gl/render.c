/* worker/render/gl/render.c — the renderer object: atlas layout and framebuffers, the triangle
 * stream, material tables, region clears (one quad draw per batch), scissored draws into a view's
 * tile and region readback. Textures are in render_textures.c, shaders in render_program.c. */
#include "worker/render/gl/render.h"

#include <GLES3/gl3.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "worker/render/gl/render_program.h"
#include "worker/render/gl/render_textures.h"

typedef struct wk_atlas {
    GLuint fbo[LM_MAX_VIEWS]; /* one per page */
    GLuint color[LM_MAX_VIEWS], depth[LM_MAX_VIEWS];
    GLuint zimage[LM_MAX_VIEWS]; /* R32F copy of the winning fragments' depth (0 if unsupported) */
    int zimage_off;              /* draws leave the depth image alone (draw buffer 1 is NONE) */
} wk_atlas;

typedef struct wk_tile {
    int page, x, y;
} wk_tile;

enum { MODE_NONE, MODE_CLEAR, MODE_SHADE };

struct wk_renderer {
    lm_view_set views;
    int width, height;           /* of one view */
    int page_w, page_h, n_pages; /* atlas pages (usually one) */
    wk_tile tiles[LM_MAX_VIEWS];
    wk_atlas *atlases[WK_RENDER_MAX_ATLASES];
    wk_render_programs progs;
    GLuint vao, vbo; /* the triangle stream */
    size_t vbo_bytes;
    GLuint quad_vao, quad_vbo; /* region quads (x, y, z per corner) */
    float *quads;
    size_t cap_quads; /* quads that fit in `quads` */
    GLuint view_ubo;  /* one view block per view, view_stride bytes apart */
    GLsizeiptr view_stride;
    wk_material_table tables[WK_RENDER_TABLES];
    int mode;
    GLuint bound_fbo, bound_tex, bound_prog, bound_mat_ubo;
    GLintptr bound_mat_offset;
    int64_t bound_view; /* -1 = none */
    int vp[4];          /* current viewport */
    int depth_images;   /* atlases carry a readable depth image (R32F renderable) */
    int scissor_on;     /* GL_SCISSOR_TEST enabled (shading) */
    int sc[4];          /* current scissor box */
    int read_buffer;    /* attachment glReadBuffer names now */
};

/* Tiles in a grid close to square for all `total` views of the job; pages when the grid exceeds
 * the framebuffer size limit. This object's views are the job's views of `deal` and sit in
 * exactly the tiles they have in the job's layout: a view's pixels depend on where its tile lies
 * (the viewport offset enters the rasteriser's arithmetic), so every split of the views renders
 * every view alike. Pages are cut to the tiles used. */
static lm_status layout_tiles(wk_renderer *r, lm_view_deal deal, uint32_t total)
{
    GLint max_rb = 0, max_vp[2] = {0, 0};
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_vp);
    int lim_w = max_rb < max_vp[0] ? max_rb : max_vp[0];
    int lim_h = max_rb < max_vp[1] ? max_rb : max_vp[1];
    if (lim_w < r->width || lim_h < r->height)
        return lm_fail(LM_E_UNSUPPORTED,
                       "view size %dx%d exceeds the device's framebuffer limit %d", r->width,
                       r->height, lim_w < lim_h ? lim_w : lim_h);
    uint32_t cols = 1;
    while (cols * cols < total)
        cols++;
    if (cols > (uint32_t)(lim_w / r->width))
        cols = (uint32_t)(lim_w / r->width);
    uint32_t rows = (total + cols - 1) / cols, rows_per_page = (uint32_t)(lim_h / r->height);
    if (rows > rows_per_page)
        rows = rows_per_page;
    uint32_t per_page = cols * rows, n = r->views.count;
    uint32_t page0 = deal.first / per_page;
    r->page_w = (int)cols * r->width;
    r->page_h = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t g = lm_view_deal_view(deal, i), k = g % per_page;
        r->tiles[i] = (wk_tile){(int)(g / per_page - page0), (int)(k % cols) * r->width,
                                (int)(k / cols) * r->height};
        if (r->tiles[i].y + r->height > r->page_h)
            r->page_h = r->tiles[i].y + r->height;
    }
    r->n_pages = r->tiles[n - 1].page + 1;
    return LM_OK;
}

static void setup_stream(wk_renderer *r)
{
    glGenVertexArrays(1, &r->vao);
    glGenBuffers(1, &r->vbo);
    glBindVertexArray(r->vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    const GLsizei stride = sizeof(lm_corner);
    glEnableVertexAttribArray(WK_ATTR_POS);
    glVertexAttribPointer(WK_ATTR_POS, 3, GL_FLOAT, GL_FALSE, stride,
                          (void *)offsetof(lm_corner, pos));
    glEnableVertexAttribArray(WK_ATTR_NORMAL);
    glVertexAttribPointer(WK_ATTR_NORMAL, 3, GL_FLOAT, GL_FALSE, stride,
                          (void *)offsetof(lm_corner, normal));
    glEnableVertexAttribArray(WK_ATTR_UV);
    glVertexAttribPointer(WK_ATTR_UV, 2, GL_FLOAT, GL_FALSE, stride,
                          (void *)offsetof(lm_corner, uv));
    glEnableVertexAttribArray(WK_ATTR_COLOR);
    glVertexAttribPointer(WK_ATTR_COLOR, 4, GL_FLOAT, GL_FALSE, stride,
                          (void *)offsetof(lm_corner, color));
}
static lm_status setup_view_blocks(wk_renderer *r)
{
    GLint align = 16;
    glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &align);
    r->view_stride = (GLsizeiptr)sizeof(wk_view_block);
    if (align > 0 && r->view_stride % align)
        r->view_stride += align - r->view_stride % align;
    size_t bytes = (size_t)r->view_stride * r->views.count;
    uint8_t *data = calloc(1, bytes);
    if (!data)
        return lm_fail(LM_E_NOMEM, "out of memory for view blocks");
    for (uint32_t h = 0; h < r->views.count; h++) {
        wk_view_block *b = (wk_view_block *)(data + (size_t)r->view_stride * h);
        memcpy(b->view_proj, r->views.views[h].view_proj, sizeof b->view_proj);
        memcpy(b->light, r->views.views[h].dir, 3 * sizeof(float));
    }
    glGenBuffers(1, &r->view_ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, r->view_ubo);
    glBufferData(GL_UNIFORM_BUFFER, (GLsizeiptr)bytes, data, GL_STATIC_DRAW);
    free(data);
    return LM_OK;
}

static void setup_quads(wk_renderer *r)
{
    glGenVertexArrays(1, &r->quad_vao);
    glGenBuffers(1, &r->quad_vbo);
    glBindVertexArray(r->quad_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->quad_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), (void *)0);
}

static void setup_state(wk_renderer *r)
{
    glActiveTexture(GL_TEXTURE0);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    r->mode = MODE_NONE;
    r->bound_view = -1;
    r->depth_images = 1; /* until an atlas says otherwise */
    r->read_buffer = GL_COLOR_ATTACHMENT0;
}

lm_status wk_renderer_create(const lm_view_set *views, lm_view_deal deal, uint32_t total,
                             wk_renderer **out)
{
    if (views->count < 1 || views->count > LM_MAX_VIEWS || total > LM_MAX_VIEWS ||
        deal.count != views->count || !lm_view_deal_fits(deal, total))
        return lm_fail(LM_E_RANGE, "views %u, %u views apart, %u of them, of %u are out of range",
                       deal.first, deal.stride, views->count, total);
    wk_renderer *r = calloc(1, sizeof *r);
    if (!r)
        return lm_fail(LM_E_NOMEM, "out of memory creating the renderer");
    r->views = *views;
    r->width = views->views[0].width;
    r->height = views->views[0].height;
    for (uint32_t i = 1; i < views->count; i++)
        if (views->views[i].width != r->width || views->views[i].height != r->height) {
            free(r);
            return lm_fail(LM_E_INVALID, "views of one set must share one size");
        }
    lm_status st = layout_tiles(r, deal, total);
    if (st == LM_OK)
        st = wk_render_programs_create(&r->progs, WK_BACKGROUND);
    if (st == LM_OK)
        st = setup_view_blocks(r);
    if (st == LM_OK) {
        setup_stream(r);
        setup_quads(r);
        setup_state(r);
        st = wk_renderer_check(r, "setting up the renderer");
    }
    if (st != LM_OK) {
        wk_renderer_destroy(r);
        return st;
    }
    *out = r;
    return LM_OK;
}

static void atlas_free(wk_renderer *r, wk_atlas *a)
{
    for (int p = 0; p < r->n_pages; p++) {
        if (a->fbo[p])
            glDeleteFramebuffers(1, &a->fbo[p]);
        if (a->color[p])
            glDeleteRenderbuffers(1, &a->color[p]);
        if (a->depth[p])
            glDeleteRenderbuffers(1, &a->depth[p]);
        if (a->zimage[p])
            glDeleteRenderbuffers(1, &a->zimage[p]);
    }
    free(a);
}

void wk_renderer_destroy(wk_renderer *r)
{
    if (!r)
        return;
    for (int i = 0; i < WK_RENDER_MAX_ATLASES; i++)
        if (r->atlases[i])
            atlas_free(r, r->atlases[i]);
    for (int t = 0; t < WK_RENDER_TABLES; t++)
        wk_material_table_free(&r->tables[t]);
    GLuint bufs[3] = {r->vbo, r->quad_vbo, r->view_ubo}, vaos[2] = {r->vao, r->quad_vao};
    glDeleteBuffers(3, bufs);
    glDeleteVertexArrays(2, vaos);
    wk_render_programs_destroy(&r->progs);
    free(r->quads);
    free(r);
}

lm_status wk_renderer_check(wk_renderer *r, const char *what)
{
    (void)r;
    GLenum e = glGetError(), first = e;
    while (e != GL_NO_ERROR)
        e = glGetError();
    if (first != GL_NO_ERROR)
        return lm_fail(LM_E_DEVICE, "GL error 0x%04x while %s", (unsigned)first, what);
    return LM_OK;
}

static void bind_fbo(wk_renderer *r, GLuint fbo)
{
    if (fbo != r->bound_fbo) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        r->bound_fbo = fbo;
        r->read_buffer = -1; /* glReadBuffer is per framebuffer */
    }
}

static void set_viewport(wk_renderer *r, int x, int y, int w, int h)
{
    if (r->vp[0] != x || r->vp[1] != y || r->vp[2] != w || r->vp[3] != h) {
        glViewport(x, y, w, h);
        r->vp[0] = x, r->vp[1] = y, r->vp[2] = w, r->vp[3] = h;
    }
}

static GLuint new_renderbuffer(GLenum format, int w, int h)
{
    GLuint rb;
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
    return rb;
}

/* Colour, depth and (where R32F is renderable) depth-image attachments of one page. Returns
 * whether the framebuffer is complete; GL errors of an unsupported R32F are consumed. */
static int page_attach(wk_renderer *r, wk_atlas *a, int p)
{
    a->color[p] = new_renderbuffer(GL_RGBA8, r->page_w, r->page_h);
    a->depth[p] = new_renderbuffer(GL_DEPTH_COMPONENT24, r->page_w, r->page_h);
    glGenFramebuffers(1, &a->fbo[p]);
    bind_fbo(r, a->fbo[p]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, a->color[p]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, a->depth[p]);
    if (r->depth_images) {
        static const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        a->zimage[p] = new_renderbuffer(GL_R32F, r->page_w, r->page_h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER,
                                  a->zimage[p]);
        glDrawBuffers(2, bufs);
        while (glGetError() != GL_NO_ERROR) /* R32F is not renderable on every GLES 3.0 device */
            ;
    }
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

static void set_scissor(wk_renderer *r, int on, int x, int y, int w, int h);

/* All of a page to background grey at depth z (and the depth image to z). */
static void clear_page(wk_renderer *r, wk_atlas *a, int p, float z)
{
    set_scissor(r, 0, 0, 0, 0, 0); /* clears obey the scissor */
    static const GLfloat grey[4] = {WK_BACKGROUND / 255.0f, WK_BACKGROUND / 255.0f,
                                    WK_BACKGROUND / 255.0f, 1.0f};
    const GLfloat zimg[4] = {z, 0, 0, 0};
    bind_fbo(r, a->fbo[p]);
    glClearBufferfv(GL_COLOR, 0, grey);
    if (a->zimage[p])
        glClearBufferfv(GL_COLOR, 1, zimg);
    glClearBufferfv(GL_DEPTH, 0, &z);
}

/* Every page of a new atlas: background at depth 1. */
static lm_status atlas_create(wk_renderer *r, uint32_t index)
{
    wk_atlas *a = calloc(1, sizeof *a);
    if (!a)
        return lm_fail(LM_E_NOMEM, "out of memory creating atlas %u", index);
    for (int p = 0; p < r->n_pages; p++) {
        if (!page_attach(r, a, p) && r->depth_images && index == 0 && p == 0) {
            atlas_free(r, a); /* first atlas: find out once whether R32F works */
            r->depth_images = 0;
            return atlas_create(r, index);
        }
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            atlas_free(r, a);
            return lm_fail(LM_E_DEVICE, "atlas framebuffer %dx%d is incomplete on this device",
                           r->page_w, r->page_h);
        }
        clear_page(r, a, p, 1.0f);
    }
    r->atlases[index] = a;
    return wk_renderer_check(r, "creating an atlas framebuffer");
}

static lm_status get_atlas(wk_renderer *r, uint32_t atlas, wk_atlas **out)
{
    LM_ASSERT(atlas < WK_RENDER_MAX_ATLASES);
    if (!r->atlases[atlas]) {
        lm_status st = atlas_create(r, atlas);
        if (st != LM_OK)
            return st;
    }
    *out = r->atlases[atlas];
    return LM_OK;
}

static lm_status bind_tile(wk_renderer *r, uint32_t atlas, uint32_t view)
{
    LM_ASSERT(view < r->views.count);
    wk_atlas *a;
    lm_status st = get_atlas(r, atlas, &a);
    if (st == LM_OK)
        bind_fbo(r, a->fbo[r->tiles[view].page]);
    return st;
}

lm_status wk_renderer_set_materials(wk_renderer *r, int table, const lm_material *mats, uint32_t n)
{
    LM_ASSERT(table >= 0 && table < WK_RENDER_TABLES);
    r->bound_tex = 0;
    r->bound_mat_ubo = 0;
    glBindTexture(GL_TEXTURE_2D, 0);
    return wk_material_table_set(&r->tables[table], mats, n);
}

uint32_t wk_renderer_material_count(const wk_renderer *r, int table)
{
    LM_ASSERT(table >= 0 && table < WK_RENDER_TABLES);
    return r->tables[table].n;
}

lm_status wk_renderer_upload(wk_renderer *r, const lm_corner *corners, size_t n_tris)
{
    size_t bytes = n_tris * 3 * sizeof(lm_corner);
    if (bytes == 0)
        return LM_OK;
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    if (bytes > r->vbo_bytes) {
        size_t cap = lm_grow_cap(r->vbo_bytes, bytes, 65536, SIZE_MAX);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)cap, NULL, GL_STREAM_DRAW);
        r->vbo_bytes = cap;
        if (glGetError() != GL_NO_ERROR) {
            r->vbo_bytes = 0;
            return lm_fail(LM_E_NOMEM, "cannot allocate a %zu-byte vertex buffer", cap);
        }
    }
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)bytes, corners);
    return LM_OK;
}

static void set_scissor(wk_renderer *r, int on, int x, int y, int w, int h)
{
    if (on != r->scissor_on) {
        if (on)
            glEnable(GL_SCISSOR_TEST);
        else
            glDisable(GL_SCISSOR_TEST);
        r->scissor_on = on;
    }
    if (on && (r->sc[0] != x || r->sc[1] != y || r->sc[2] != w || r->sc[3] != h)) {
        glScissor(x, y, w, h);
        r->sc[0] = x, r->sc[1] = y, r->sc[2] = w, r->sc[3] = h;
    }
}

static void use_clear_mode(wk_renderer *r)
{
    set_scissor(r, 0, 0, 0, 0, 0);
    if (r->mode == MODE_CLEAR)
        return;
    glUseProgram(r->progs.clear);
    glBindVertexArray(r->quad_vao);
    glDepthFunc(GL_ALWAYS);
    r->bound_prog = r->progs.clear;
    r->mode = MODE_CLEAR;
}

lm_status wk_renderer_clear_all(wk_renderer *r, uint32_t atlas)
{
    wk_atlas *a;
    lm_status st = get_atlas(r, atlas, &a);
    for (int p = 0; st == LM_OK && p < r->n_pages; p++)
        clear_page(r, a, p, 1.0f);
    return st;
}

/* Two triangles over rect of a view, in page NDC, at the far plane. */
static float *put_quad(const wk_renderer *r, float *q, uint32_t view, const wk_rect *rc)
{
    const wk_tile *t = &r->tiles[view];
    float x0 = 2.0f * (float)(t->x + rc->x0) / (float)r->page_w - 1.0f;
    float x1 = 2.0f * (float)(t->x + rc->x1) / (float)r->page_w - 1.0f;
    float y0 = 2.0f * (float)(t->y + rc->y0) / (float)r->page_h - 1.0f;
    float y1 = 2.0f * (float)(t->y + rc->y1) / (float)r->page_h - 1.0f;
    const float v[18] = {x0, y0, 1, x1, y0, 1, x1, y1, 1, x0, y0, 1, x1, y1, 1, x0, y1, 1};
    memcpy(q, v, sizeof v);
    return q + 18;
}

static lm_status reserve_quads(wk_renderer *r, size_t n)
{
    if (n <= r->cap_quads)
        return LM_OK;
    size_t cap = lm_grow_cap(r->cap_quads, n, 256, SIZE_MAX);
    float *q = realloc(r->quads, cap * 18 * sizeof *q);
    if (!q)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu region quads", cap);
    r->quads = q;
    r->cap_quads = cap;
    return LM_OK;
}

lm_status wk_renderer_clear_regions(wk_renderer *r, uint32_t atlas, const uint32_t *views,
                                    const wk_rect *rects, size_t n)
{
    wk_atlas *a;
    lm_status st = get_atlas(r, atlas, &a);
    if (st == LM_OK)
        st = reserve_quads(r, n);
    for (int p = 0; st == LM_OK && p < r->n_pages; p++) {
        float *q = r->quads;
        for (size_t i = 0; i < n; i++) {
            LM_ASSERT(views[i] < r->views.count && rects[i].x0 >= 0 && rects[i].y0 >= 0 &&
                      rects[i].x1 <= r->width && rects[i].y1 <= r->height);
            if (r->tiles[views[i]].page == p && !wk_rect_empty(&rects[i]))
                q = put_quad(r, q, views[i], &rects[i]);
        }
        size_t verts = (size_t)(q - r->quads) / 3;
        if (verts == 0)
            continue;
        bind_fbo(r, a->fbo[p]);
        set_viewport(r, 0, 0, r->page_w, r->page_h);
        use_clear_mode(r);
        glBindBuffer(GL_ARRAY_BUFFER, r->quad_vbo);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(verts * 3 * sizeof(float)), r->quads,
                     GL_STREAM_DRAW);
        glDrawArrays(GL_TRIANGLES, 0, (GLsizei)verts);
    }
    return st;
}

/* Program, texture and material block of material m. */
static void use_material(wk_renderer *r, const wk_material_table *mt, uint32_t m)
{
    GLuint nrm = mt->nrm ? mt->nrm[m] : 0;
    GLuint prog = nrm ? r->progs.shade_normal[mt->tex[m] != 0] : r->progs.shade[mt->tex[m] != 0];
    if (prog != r->bound_prog) {
        glUseProgram(prog);
        r->bound_prog = prog;
    }
    if (nrm) { /* unit 1 (rarely used: not tracked) */
        glActiveTexture(GL_TEXTURE0 + WK_NORMAL_MAP_UNIT);
        glBindTexture(GL_TEXTURE_2D, nrm);
        glActiveTexture(GL_TEXTURE0);
    }
    if (mt->tex[m] && mt->tex[m] != r->bound_tex) {
        glBindTexture(GL_TEXTURE_2D, mt->tex[m]);
        r->bound_tex = mt->tex[m];
    }
    GLintptr off = (GLintptr)mt->stride * m;
    if (mt->ubo != r->bound_mat_ubo || off != r->bound_mat_offset) {
        glBindBufferRange(GL_UNIFORM_BUFFER, WK_BLOCK_MATERIAL, mt->ubo, off,
                          (GLsizeiptr)sizeof(wk_material_block));
        r->bound_mat_ubo = mt->ubo;
        r->bound_mat_offset = off;
    }
}

static void use_view(wk_renderer *r, uint32_t view, const wk_rect *rc)
{
    const wk_tile *t = &r->tiles[view];
    set_viewport(r, t->x, t->y, r->width, r->height);
    set_scissor(r, 1, t->x + rc->x0, t->y + rc->y0, rc->x1 - rc->x0, rc->y1 - rc->y0);
    if (r->mode != MODE_SHADE) {
        glBindVertexArray(r->vao);
        glDepthFunc(GL_LESS);
        r->mode = MODE_SHADE;
    }
    if (r->bound_view != (int64_t)view) {
        glBindBufferRange(GL_UNIFORM_BUFFER, WK_BLOCK_VIEW, r->view_ubo,
                          (GLintptr)r->view_stride * view, (GLsizeiptr)sizeof(wk_view_block));
        r->bound_view = view;
    }
}

lm_status wk_renderer_draw(wk_renderer *r, int table, const wk_draw *d, const uint32_t *materials)
{
    LM_ASSERT(table >= 0 && table < WK_RENDER_TABLES);
    if (d->count == 0)
        return LM_OK;
    lm_status st = bind_tile(r, d->atlas, d->view);
    if (st != LM_OK)
        return st;
    if (wk_rect_empty(&d->rect))
        return LM_OK;
    LM_ASSERT(d->rect.x0 >= 0 && d->rect.y0 >= 0 && d->rect.x1 <= r->width &&
              d->rect.y1 <= r->height);
    use_view(r, d->view, &d->rect);
    const wk_material_table *mt = &r->tables[table];
    size_t i = d->first, end = d->first + d->count;
    while (i < end) {
        uint32_t m = materials[i];
        size_t j = i + 1;
        while (j < end && materials[j] == m)
            j++;
        LM_ASSERT(m < mt->n);
        use_material(r, mt, m);
        glDrawArrays(GL_TRIANGLES, (GLint)(3 * i), (GLsizei)(3 * (j - i)));
        i = j;
    }
    return LM_OK;
}

static void read_region(wk_renderer *r, GLenum buffer, uint32_t view, const wk_rect *rect,
                        GLenum format, GLenum type, void *out)
{
    if ((int)buffer != r->read_buffer) {
        glReadBuffer(buffer);
        r->read_buffer = (int)buffer;
    }
    const wk_tile *t = &r->tiles[view];
    glReadPixels(t->x + rect->x0, t->y + rect->y0, rect->x1 - rect->x0, rect->y1 - rect->y0, format,
                 type, out);
}

lm_status wk_renderer_read(wk_renderer *r, uint32_t atlas, uint32_t view, const wk_rect *rect,
                           uint8_t *rgba)
{
    if (wk_rect_empty(rect))
        return LM_OK;
    lm_status st = bind_tile(r, atlas, view);
    if (st == LM_OK)
        read_region(r, GL_COLOR_ATTACHMENT0, view, rect, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    return st;
}

lm_status wk_renderer_write_depth_images(wk_renderer *r, uint32_t atlas, int on)
{
    static const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    static const GLenum colour[2] = {GL_COLOR_ATTACHMENT0, GL_NONE};
    wk_atlas *a;
    lm_status st = get_atlas(r, atlas, &a);
    if (st != LM_OK || !r->depth_images || a->zimage_off == !on)
        return st;
    for (int p = 0; p < r->n_pages; p++) {
        bind_fbo(r, a->fbo[p]);
        glDrawBuffers(2, on ? both : colour);
    }
    a->zimage_off = !on;
    return LM_OK;
}

int wk_renderer_has_depth_images(wk_renderer *r)
{
    wk_atlas *a;
    return get_atlas(r, 0, &a) == LM_OK && r->depth_images;
}

lm_status wk_renderer_read_depth(wk_renderer *r, uint32_t atlas, uint32_t view, const wk_rect *rect,
                                 float *depth)
{
    if (wk_rect_empty(rect))
        return LM_OK;
    if (!r->depth_images)
        return lm_fail(LM_E_UNSUPPORTED, "this device has no readable depth images");
    lm_status st = bind_tile(r, atlas, view);
    if (st == LM_OK)
        read_region(r, GL_COLOR_ATTACHMENT1, view, rect, GL_RED, GL_FLOAT, depth);
    return st;
}
