/* worker/render/gl/render_textures.c — material tables on the device: RGBA8 textures with mipmaps
 * and repeat wrapping, uploaded bottom row first so that uv (0,0) is the image's bottom-left corner
 * (the OBJ/GL convention); diffuse colours as uniform blocks. The table is filled as the CPU
 * backend's is (worker/render/shared/materials.h). */
#include "worker/render/gl/render_textures.h"

#include <stdlib.h>
#include <string.h>

#include "worker/render/gl/render_program.h"
#include "worker/render/shared/materials.h"

static void set_params(void)
{
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
}

static lm_status upload(const lm_image *img, GLuint *out)
{
    GLint max = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max);
    if (img->width > max || img->height > max)
        return lm_fail(LM_E_UNSUPPORTED, "texture %dx%d exceeds the device limit %d", img->width,
                       img->height, max);
    if (img->channels != 4 || !img->pixels)
        return lm_fail(LM_E_INVALID, "texture is not RGBA8 (%d channels)", img->channels);
    size_t row = (size_t)img->width * 4;
    uint8_t *flipped = malloc(row * img->height);
    if (!flipped)
        return lm_fail(LM_E_NOMEM, "out of memory uploading a %dx%d texture", img->width,
                       img->height);
    for (int y = 0; y < img->height; y++)
        memcpy(flipped + row * y, img->pixels + row * (img->height - 1 - y), row);
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, img->width, img->height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 flipped);
    free(flipped);
    glGenerateMipmap(GL_TEXTURE_2D);
    set_params();
    if (glGetError() != GL_NO_ERROR) {
        glDeleteTextures(1, &tex);
        return lm_fail(LM_E_DEVICE, "uploading a %dx%d texture failed", img->width, img->height);
    }
    *out = tex;
    return LM_OK;
}

/* One texture of the table (wk_texture_make, materials.h). */
static lm_status make_texture(const lm_image *img, void *handle)
{
    return upload(img, handle);
}

static void clear_table(wk_material_table *t)
{
    for (uint32_t i = 0; i < t->n; i++) {
        if (t->tex[i])
            glDeleteTextures(1, &t->tex[i]);
        if (t->nrm && t->nrm[i])
            glDeleteTextures(1, &t->nrm[i]);
    }
    free(t->nrm);
    t->nrm = NULL;
    if (t->ubo)
        glDeleteBuffers(1, &t->ubo);
    t->ubo = 0;
    free(t->tex);
    free(t->diffuse);
    t->tex = NULL;
    t->diffuse = NULL;
    t->n = 0;
}

/* The diffuse colours as uniform blocks at the device's offset alignment. */
static lm_status upload_blocks(wk_material_table *t)
{
    GLint align = 16;
    glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &align);
    t->stride = (GLsizeiptr)sizeof(wk_material_block);
    if (align > 0 && t->stride % align)
        t->stride += align - t->stride % align;
    size_t bytes = (size_t)t->stride * (t->n ? t->n : 1);
    uint8_t *data = calloc(1, bytes);
    if (!data)
        return lm_fail(LM_E_NOMEM, "out of memory for %u material blocks", t->n);
    for (uint32_t i = 0; i < t->n; i++)
        memcpy(data + (size_t)t->stride * i, t->diffuse[i], sizeof(wk_material_block));
    glGenBuffers(1, &t->ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, t->ubo);
    glBufferData(GL_UNIFORM_BUFFER, (GLsizeiptr)bytes, data, GL_STATIC_DRAW);
    free(data);
    return glGetError() == GL_NO_ERROR ? LM_OK
                                       : lm_fail(LM_E_DEVICE, "uploading material blocks failed");
}

lm_status wk_material_table_set(wk_material_table *t, const lm_material *mats, uint32_t n)
{
    clear_table(t);
    void *tex;
    lm_status st =
        wk_materials_fill(mats, n, sizeof *t->tex, make_texture, &t->n, &t->diffuse, &tex);
    t->tex = tex;
    if (st == LM_OK)
        st = upload_blocks(t);
    void *nrm = NULL;
    if (st == LM_OK)
        st = wk_materials_fill_normal_maps(mats, n, sizeof *t->nrm, make_texture, &nrm);
    t->nrm = nrm;
    glBindTexture(GL_TEXTURE_2D, 0);
    if (st != LM_OK)
        clear_table(t);
    return st;
}

void wk_material_table_free(wk_material_table *t)
{
    clear_table(t);
}
