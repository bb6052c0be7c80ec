/* worker/render.c — the renderer object: atlas layout and framebuffers, the triangle stream,
 * material tables, scissored draws into a view's tile and region readback. Textures are in
 * render_textures.c, shaders in render_program.c. */
#include "worker/render.h"

#include <GLES3/gl3.h>
#include <stdlib.h>
#include <string.h>

#include "worker/render_program.h"
#include "worker/render_textures.h"

typedef struct wk_atlas {
    GLuint fbo[LM_MAX_VIEWS]; /* one per page; 0 = not created */
    GLuint color[LM_MAX_VIEWS], depth[LM_MAX_VIEWS];
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
    GLuint vao, vbo;             /* the triangle stream */
    size_t vbo_bytes;
    GLuint clear_vao, clear_vbo; /* a quad over the whole viewport */
    GLuint view_ubo;             /* one view block per view, view_stride bytes apart */
    GLsizeiptr view_stride;
    wk_material_table tables[WK_RENDER_TABLES];
    int mode;
    GLuint bound_fbo, bound_tex, bound_prog, bound_mat_ubo;
    GLintptr bound_mat_offset;
    int64_t bound_view; /* -1 = none */
};

/* Tiles in a grid close to square; pages when the grid exceeds the framebuffer size limit. */
static lm_status layout_tiles(wk_renderer *r)
{
    GLint max_rb = 0, max_vp[2] = {0, 0};
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_vp);
    int lim_w = max_rb < max_vp[0] ? max_rb : max_vp[0];
    int lim_h = max_rb < max_vp[1] ? max_rb : max_vp[1];
    if (lim_w < r->width || lim_h < r->height)
        return lm_fail(LM_E_UNSUPPORTED, "view size %dx%d exceeds the device's framebuffer limit %d",
                       r->width, r->height, lim_w < lim_h ? lim_w : lim_h);
    uint32_t n = r->views.count, cols = 1;
    while (cols * cols < n)
        cols++;
    if (cols > (uint32_t)(lim_w / r->width))
        cols = (uint32_t)(lim_w / r->width);
    uint32_t rows = (n + cols - 1) / cols, rows_per_page = (uint32_t)(lim_h / r->height);
    if (rows > rows_per_page)
        rows = rows_per_page;
    uint32_t per_page = cols * rows;
    r->page_w = (int)cols * r->width;
    r->page_h = (int)rows * r->height;
    r->n_pages = (int)((n + per_page - 1) / per_page);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t k = i % per_page;
        r->tiles[i] = (wk_tile){(int)(i / per_page), (int)(k % cols) * r->width,
                                (int)(k / cols) * r->height};
    }
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

static void setup_clear_quad(wk_renderer *r)
{
    static const float quad[12] = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
    glGenVertexArrays(1, &r->clear_vao);
    glGenBuffers(1, &r->clear_vbo);
    glBindVertexArray(r->clear_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->clear_vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), (void *)0);
}

/* Every view's block (view-projection, light direction) in one uniform buffer. */
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

static void setup_state(wk_renderer *r)
{
    glActiveTexture(GL_TEXTURE0);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glEnable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    r->mode = MODE_NONE;
    r->bound_view = -1;
}

lm_status wk_renderer_create(const lm_view_set *views, wk_renderer **out)
{
    if (views->count < 1 || views->count > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "view count %u is out of range", views->count);
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
    lm_status st = layout_tiles(r);
    if (st == LM_OK)
        st = wk_render_programs_create(&r->progs, WK_BACKGROUND);
    if (st == LM_OK)
        st = setup_view_blocks(r);
    if (st == LM_OK) {
        setup_stream(r);
        setup_clear_quad(r);
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
    GLuint bufs[3] = {r->vbo, r->clear_vbo, r->view_ubo}, vaos[2] = {r->vao, r->clear_vao};
    glDeleteBuffers(3, bufs);
    glDeleteVertexArrays(2, vaos);
    wk_render_programs_destroy(&r->progs);
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

static lm_status atlas_create(wk_renderer *r, uint32_t index)
{
    wk_atlas *a = calloc(1, sizeof *a);
    if (!a)
        return lm_fail(LM_E_NOMEM, "out of memory creating atlas %u", index);
    for (int p = 0; p < r->n_pages; p++) {
        glGenRenderbuffers(1, &a->color[p]);
        glBindRenderbuffer(GL_RENDERBUFFER, a->color[p]);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, r->page_w, r->page_h);
        glGenRenderbuffers(1, &a->depth[p]);
        glBindRenderbuffer(GL_RENDERBUFFER, a->depth[p]);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, r->page_w, r->page_h);
        glGenFramebuffers(1, &a->fbo[p]);
        glBindFramebuffer(GL_FRAMEBUFFER, a->fbo[p]);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, a->color[p]);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, a->depth[p]);
        r->bound_fbo = a->fbo[p];
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            atlas_free(r, a);
            return lm_fail(LM_E_DEVICE, "atlas framebuffer %dx%d is incomplete on this device",
                           r->page_w, r->page_h);
        }
    }
    r->atlases[index] = a;
    return wk_renderer_check(r, "creating an atlas framebuffer");
}

static lm_status bind_tile(wk_renderer *r, uint32_t atlas, uint32_t view)
{
    LM_ASSERT(atlas < WK_RENDER_MAX_ATLASES && view < r->views.count);
    if (!r->atlases[atlas]) {
        lm_status st = atlas_create(r, atlas);
        if (st != LM_OK)
            return st;
    }
    GLuint fbo = r->atlases[atlas]->fbo[r->tiles[view].page];
    if (fbo != r->bound_fbo) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        r->bound_fbo = fbo;
    }
    return LM_OK;
}

lm_status wk_renderer_set_materials(wk_renderer *r, int table, const lm_material *mats,
                                    uint32_t n)
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
    if (bytes > r->vbo_bytes) {
        size_t cap = r->vbo_bytes ? r->vbo_bytes : 65536;
        while (cap < bytes)
            cap *= 2;
        glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)cap, NULL, GL_STREAM_DRAW);
        r->vbo_bytes = cap;
        if (glGetError() != GL_NO_ERROR) {
            r->vbo_bytes = 0;
            return lm_fail(LM_E_NOMEM, "cannot allocate a %zu-byte vertex buffer", cap);
        }
    }
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)bytes, corners);
    return LM_OK;
}

/* Framebuffer, viewport and scissor for rect of a view. */
static lm_status target_rect(wk_renderer *r, uint32_t atlas, uint32_t view, const wk_rect *rc)
{
    LM_ASSERT(rc->x0 >= 0 && rc->y0 >= 0 && rc->x1 <= r->width && rc->y1 <= r->height);
    lm_status st = bind_tile(r, atlas, view);
    if (st != LM_OK)
        return st;
    const wk_tile *t = &r->tiles[view];
    glViewport(t->x, t->y, r->width, r->height);
    glScissor(t->x + rc->x0, t->y + rc->y0, rc->x1 - rc->x0, rc->y1 - rc->y0);
    return LM_OK;
}

lm_status wk_renderer_clear(wk_renderer *r, uint32_t atlas, uint32_t view, const wk_rect *rect)
{
    if (wk_rect_empty(rect))
        return LM_OK;
    lm_status st = target_rect(r, atlas, view, rect);
    if (st != LM_OK)
        return st;
    if (getenv("HACK_GLCLEAR")) { glDepthMask(GL_TRUE); glClearColor(128/255.0f,128/255.0f,128/255.0f,1); glClearDepthf(1.0f); glClear(GL_COLOR_BUFFER_BIT|GL_DEPTH_BUFFER_BIT); return LM_OK; }
    if (r->mode != MODE_CLEAR) {
        glUseProgram(r->progs.clear);
        glBindVertexArray(r->clear_vao);
        glDepthFunc(GL_ALWAYS);
        r->bound_prog = r->progs.clear;
        r->mode = MODE_CLEAR;
    }
    glDrawArrays(GL_TRIANGLES, 0, 6);
    return LM_OK;
}

/* Program, texture and material block of material m. */
static void use_material(wk_renderer *r, const wk_material_table *mt, uint32_t m)
{
    GLuint prog = r->progs.shade[mt->tex[m] != 0];
    if (prog != r->bound_prog) {
        glUseProgram(prog);
        r->bound_prog = prog;
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

lm_status wk_renderer_draw(wk_renderer *r, int table, const wk_draw *d, const uint32_t *materials)
{
    LM_ASSERT(table >= 0 && table < WK_RENDER_TABLES);
    if (wk_rect_empty(&d->rect) || d->count == 0)
        return LM_OK;
    lm_status st = target_rect(r, d->atlas, d->view, &d->rect);
    if (st != LM_OK)
        return st;
    if (r->mode != MODE_SHADE) {
        glBindVertexArray(r->vao);
        glDepthFunc(GL_LESS);
        r->mode = MODE_SHADE;
    }
    if (r->bound_view != (int64_t)d->view) {
        glBindBufferRange(GL_UNIFORM_BUFFER, WK_BLOCK_VIEW, r->view_ubo,
                          (GLintptr)r->view_stride * d->view, (GLsizeiptr)sizeof(wk_view_block));
        r->bound_view = d->view;
    }
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

lm_status wk_renderer_read(wk_renderer *r, uint32_t atlas, uint32_t view, const wk_rect *rect,
                           uint8_t *rgba)
{
    if (wk_rect_empty(rect))
        return LM_OK;
    lm_status st = bind_tile(r, atlas, view);
    if (st != LM_OK)
        return st;
    const wk_tile *t = &r->tiles[view];
    glReadPixels(t->x + rect->x0, t->y + rect->y0, rect->x1 - rect->x0, rect->y1 - rect->y0,
                 GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    return LM_OK;
}
