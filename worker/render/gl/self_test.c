/* worker/render/gl/self_test.c — renders a known image on a context and checks it pixel by pixel:
 * a blue clear, then a red triangle over the lower-left half of a 32x32 RGBA8 framebuffer
 * object. Proves the device really rasterises (not only that a context exists). */
#include "worker/render/gl/self_test.h"

#include <GLES3/gl3.h>
#include <stdint.h>
#include <string.h>

#define ST_SIZE 32

typedef struct st_objects {
    GLuint fbo, rbo, vbo, vao, prog;
} st_objects;

static const char *const st_vs = "#version 300 es\n"
                                 "layout(location = 0) in vec2 pos;\n"
                                 "void main() { gl_Position = vec4(pos, 0.0, 1.0); }\n";
static const char *const st_fs = "#version 300 es\n"
                                 "precision mediump float;\n"
                                 "out vec4 color;\n"
                                 "void main() { color = vec4(1.0, 0.0, 0.0, 1.0); }\n";

static GLuint compile(GLenum type, const char *src)
{
    GLuint sh = glCreateShader(type);
    GLint ok = 0;
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        glDeleteShader(sh);
        return 0;
    }
    return sh;
}

static lm_status build_program(st_objects *o)
{
    GLuint vs = compile(GL_VERTEX_SHADER, st_vs), fs = compile(GL_FRAGMENT_SHADER, st_fs);
    GLint ok = 0;
    if (vs && fs) {
        o->prog = glCreateProgram();
        glAttachShader(o->prog, vs);
        glAttachShader(o->prog, fs);
        glLinkProgram(o->prog);
        glGetProgramiv(o->prog, GL_LINK_STATUS, &ok);
    }
    glDeleteShader(vs);
    glDeleteShader(fs);
    if (!ok)
        return lm_fail(LM_E_DEVICE, "self-test: GLSL ES 3.00 shaders failed to %s",
                       vs && fs ? "link" : "compile");
    return LM_OK;
}

static lm_status build_targets(st_objects *o)
{
    static const GLfloat tri[] = {-1.f, -1.f, 1.f, -1.f, -1.f, 1.f};
    glGenFramebuffers(1, &o->fbo);
    glGenRenderbuffers(1, &o->rbo);
    glBindRenderbuffer(GL_RENDERBUFFER, o->rbo);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, ST_SIZE, ST_SIZE);
    glBindFramebuffer(GL_FRAMEBUFFER, o->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, o->rbo);
    GLenum fb = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (fb != GL_FRAMEBUFFER_COMPLETE)
        return lm_fail(LM_E_DEVICE, "self-test: RGBA8 framebuffer incomplete (status 0x%04x)",
                       (unsigned)fb);
    glGenVertexArrays(1, &o->vao);
    glBindVertexArray(o->vao);
    glGenBuffers(1, &o->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, o->vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof tri, tri, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (const void *)0);
    glEnableVertexAttribArray(0);
    return LM_OK;
}

static void release(st_objects *o)
{
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteVertexArrays(1, &o->vao);
    glDeleteBuffers(1, &o->vbo);
    glDeleteFramebuffers(1, &o->fbo);
    glDeleteRenderbuffers(1, &o->rbo);
    glDeleteProgram(o->prog);
}

/* Lower-left half (x + y < size) must be red, the rest blue; the diagonal may be either. */
static lm_status check_pixels(const uint8_t *px, int *red_pixels)
{
    int red = 0;
    for (int y = 0; y < ST_SIZE; y++) {
        for (int x = 0; x < ST_SIZE; x++) {
            const uint8_t *p = px + 4 * (y * ST_SIZE + x);
            int is_red = p[0] == 255 && p[1] == 0 && p[2] == 0 && p[3] == 255;
            int is_blue = p[0] == 0 && p[1] == 0 && p[2] == 255 && p[3] == 255;
            int expect_red = x + y<ST_SIZE - 1, expect_blue = x + y> ST_SIZE - 1;
            if ((expect_red && !is_red) || (expect_blue && !is_blue) || (!is_red && !is_blue))
                return lm_fail(LM_E_DEVICE, "self-test: pixel (%d,%d) is %u,%u,%u,%u, expected %s",
                               x, y, p[0], p[1], p[2], p[3], expect_red ? "red" : "blue");
            red += is_red;
        }
    }
    if (red_pixels)
        *red_pixels = red;
    return LM_OK;
}

lm_status wk_self_test_run(wk_gl_context *ctx, int *red_pixels)
{
    uint8_t px[ST_SIZE * ST_SIZE * 4]; /* 4 KiB */
    st_objects o;
    memset(&o, 0, sizeof o);
    lm_status st = wk_gl_context_make_current(ctx);
    if (st != LM_OK)
        return st;
    while (glGetError() != GL_NO_ERROR) {
    }
    st = build_program(&o);
    if (st == LM_OK)
        st = build_targets(&o);
    if (st == LM_OK) {
        glViewport(0, 0, ST_SIZE, ST_SIZE);
        glClearColor(0.f, 0.f, 1.f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT);
        glUseProgram(o.prog);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        memset(px, 0x7f, sizeof px);
        glReadPixels(0, 0, ST_SIZE, ST_SIZE, GL_RGBA, GL_UNSIGNED_BYTE, px);
        GLenum err = glGetError();
        st = err != GL_NO_ERROR
                 ? lm_fail(LM_E_DEVICE, "self-test: GL error 0x%04x while drawing", (unsigned)err)
                 : check_pixels(px, red_pixels);
    }
    release(&o);
    return st;
}
