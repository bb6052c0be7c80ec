/* worker/render/gl/render_program.c — the shaders: Gouraud lighting with one light at the viewer,
 * per vertex (two-sided, normals used as given), modulated per fragment by the material's texture
 * (with a normal map: lit per fragment);
 * and the clear program that paints quads background grey at the depth they carry (drawn with depth
 * ALWAYS: opening regions at depth 1 and closing them at depth 0, see render.h). */
#include "worker/render/gl/render_program.h"

#include <stdio.h>

/* The textured variant; the plain one drops the texture coordinates (fewer varyings make Mesa's
 * triangle setup and interpolation cheaper). Alpha plays no part in the image. */
#define SHADE_VS_HEAD                                                                              \
    "#version 300 es\n"                                                                            \
    "precision highp float;\n"                                                                     \
    "layout(location = 0) in vec3 a_pos;\n"                                                        \
    "layout(location = 1) in vec3 a_normal;\n"                                                     \
    "layout(location = 2) in vec2 a_uv;\n"                                                         \
    "layout(location = 3) in vec4 a_color;\n"                                                      \
    "layout(std140) uniform ViewBlock { mat4 u_view_proj; vec4 u_light; };\n"                      \
    "layout(std140) uniform MaterialBlock { vec4 u_diffuse; };\n"                                  \
    "out vec3 v_color;\n"

#define SHADE_VS_BODY                                                                              \
    "    gl_Position = u_view_proj * vec4(a_pos, 1.0);\n"                                          \
    "    float d = abs(dot(a_normal, u_light.xyz));\n"                                             \
    "    v_color = a_color.rgb * u_diffuse.rgb * (0.15 + 0.85 * d);\n"

static const char *const shade_vs_textured =
    SHADE_VS_HEAD "out vec2 v_uv;\n"
                  "void main() {\n" SHADE_VS_BODY "    v_uv = a_uv;\n"
                  "}\n";

static const char *const shade_vs_plain = SHADE_VS_HEAD "void main() {\n" SHADE_VS_BODY "}\n";

static const char *const shade_fs_textured =
    "#version 300 es\n"
    "precision highp float;\n"
    "uniform sampler2D u_texture;\n"
    "in vec2 v_uv;\n"
    "in vec3 v_color;\n"
    "layout(location = 0) out vec4 o_color;\n"
    "layout(location = 1) out float o_depth;\n"
    "void main() {\n"
    "    o_color = vec4(clamp(texture(u_texture, v_uv).rgb * v_color, 0.0, 1.0), 1.0);\n"
    "    o_depth = gl_FragCoord.z;\n"
    "}\n";

static const char *const shade_fs_plain = "#version 300 es\n"
                                          "precision highp float;\n"
                                          "in vec3 v_color;\n"
                                          "layout(location = 0) out vec4 o_color;\n"
                                          "layout(location = 1) out float o_depth;\n"
                                          "void main() {\n"
                                          "    o_color = vec4(clamp(v_color, 0.0, 1.0), 1.0);\n"
                                          "    o_depth = gl_FragCoord.z;\n"
                                          "}\n";

/* Normal-mapped materials (variants without and with a colour texture): lit per fragment by
 * 0.15 + 0.85 |n·l|, n = normalize(T x + B y + N z) with (x, y, z) = 2 × the map's texel - 1 and
 * the triangle's UV-derivative frame from the screen derivatives of position and uv (a triangle's
 * own frame, as the CPU rasteriser's, common/tangents.h), made orthogonal to the interpolated
 * normal per fragment, B = w (N × T). */
#define NORMAL_VS                                                                                  \
    SHADE_VS_HEAD "out vec2 v_uv;\n"                                                               \
                  "out vec3 v_pos;\n"                                                              \
                  "out vec3 v_normal;\n"                                                           \
                  "void main() {\n"                                                                \
                  "    gl_Position = u_view_proj * vec4(a_pos, 1.0);\n"                            \
                  "    v_color = a_color.rgb * u_diffuse.rgb;\n"                                   \
                  "    v_uv = a_uv;\n"                                                             \
                  "    v_pos = a_pos;\n"                                                           \
                  "    v_normal = a_normal;\n"                                                     \
                  "}\n"

#define NORMAL_FS_HEAD                                                                             \
    "#version 300 es\n"                                                                            \
    "precision highp float;\n"                                                                     \
    "layout(std140) uniform ViewBlock { mat4 u_view_proj; vec4 u_light; };\n"                      \
    "uniform sampler2D u_texture;\n"                                                               \
    "uniform sampler2D u_normal_map;\n"                                                            \
    "in vec2 v_uv;\n"                                                                              \
    "in vec3 v_color;\n"                                                                           \
    "in vec3 v_pos;\n"                                                                             \
    "in vec3 v_normal;\n"                                                                          \
    "layout(location = 0) out vec4 o_color;\n"                                                     \
    "layout(location = 1) out float o_depth;\n"                                                    \
    "float light() {\n"                                                                            \
    "    vec3 px = dFdx(v_pos), py = dFdy(v_pos);\n"                                               \
    "    vec2 ux = dFdx(v_uv), uy = dFdy(v_uv);\n"                                                 \
    "    float s = ux.x * uy.y - uy.x * ux.y < 0.0 ? -1.0 : 1.0;\n"                                \
    "    vec3 t = (px * uy.y - py * ux.y) * s, b = (py * ux.x - px * uy.x) * s;\n"                 \
    "    float nl = length(v_normal);\n"                                                           \
    "    vec3 n = nl > 0.0 ? v_normal / nl : vec3(0.0, 0.0, 1.0);\n"                               \
    "    t -= n * dot(n, t);\n"                                                                    \
    "    float tl = length(t);\n"                                                                  \
    "    t = tl > 0.0 ? t / tl : (abs(n.x) < 0.9 ? normalize(vec3(1.0, 0.0, 0.0) - n * n.x)\n"     \
    "                                            : normalize(vec3(0.0, 1.0, 0.0) - n * n.y));\n"   \
    "    vec3 c = cross(n, t);\n"                                                                  \
    "    vec3 m = texture(u_normal_map, v_uv).rgb * 2.0 - 1.0;\n"                                  \
    "    vec3 d = m.x * t + m.y * (dot(c, b) < 0.0 ? -c : c) + m.z * n;\n"                         \
    "    float dl = length(d);\n"                                                                  \
    "    return 0.15 + 0.85 * (dl > 0.0 ? abs(dot(d, u_light.xyz)) / dl : 0.0);\n"                 \
    "}\n"

static const char *const normal_vs = NORMAL_VS;

static const char *const normal_fs_plain =
    NORMAL_FS_HEAD "void main() {\n"
                   "    o_color = vec4(clamp(v_color * light(), 0.0, 1.0), 1.0);\n"
                   "    o_depth = gl_FragCoord.z;\n"
                   "}\n";

static const char *const normal_fs_textured =
    NORMAL_FS_HEAD "void main() {\n"
                   "    o_color = vec4(clamp(texture(u_texture, v_uv).rgb * (v_color * light()),\n"
                   "                         0.0, 1.0), 1.0);\n"
                   "    o_depth = gl_FragCoord.z;\n"
                   "}\n";

static const char *const clear_vs = "#version 300 es\n"
                                    "precision highp float;\n"
                                    "layout(location = 0) in vec3 a_pos;\n"
                                    "void main() { gl_Position = vec4(a_pos, 1.0); }\n";

static const char *const clear_fs_fmt = "#version 300 es\n"
                                        "precision highp float;\n"
                                        "layout(location = 0) out vec4 o_color;\n"
                                        "layout(location = 1) out float o_depth;\n"
                                        "void main() {\n"
                                        "    o_color = vec4(vec3(%d.0 / 255.0), 1.0);\n"
                                        "    o_depth = gl_FragCoord.z;\n"
                                        "}\n";

static lm_status compile(GLenum kind, const char *src, GLuint *out)
{
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        glDeleteShader(s);
        return lm_fail(LM_E_DEVICE, "%s shader does not compile: %s",
                       kind == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
    }
    *out = s;
    return LM_OK;
}

static lm_status link(const char *vs_src, const char *fs_src, GLuint *out)
{
    GLuint vs = 0, fs = 0;
    lm_status st = compile(GL_VERTEX_SHADER, vs_src, &vs);
    if (st == LM_OK)
        st = compile(GL_FRAGMENT_SHADER, fs_src, &fs);
    if (st != LM_OK) {
        glDeleteShader(vs);
        return st;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        glDeleteProgram(p);
        return lm_fail(LM_E_DEVICE, "render program does not link: %s", log);
    }
    *out = p;
    return LM_OK;
}

static void bind_blocks(GLuint p)
{
    glUniformBlockBinding(p, glGetUniformBlockIndex(p, "ViewBlock"), WK_BLOCK_VIEW);
    glUniformBlockBinding(p, glGetUniformBlockIndex(p, "MaterialBlock"), WK_BLOCK_MATERIAL);
    GLint tex = glGetUniformLocation(p, "u_texture");
    if (tex >= 0) {
        glUseProgram(p);
        glUniform1i(tex, 0);
    }
    GLint nrm = glGetUniformLocation(p, "u_normal_map");
    if (nrm >= 0) {
        glUseProgram(p);
        glUniform1i(nrm, WK_NORMAL_MAP_UNIT);
    }
}

lm_status wk_render_programs_create(wk_render_programs *out, int background)
{
    char clear_fs[256];
    snprintf(clear_fs, sizeof clear_fs, clear_fs_fmt, background);
    lm_status st = link(shade_vs_plain, shade_fs_plain, &out->shade[0]);
    if (st == LM_OK)
        st = link(shade_vs_textured, shade_fs_textured, &out->shade[1]);
    if (st == LM_OK)
        st = link(normal_vs, normal_fs_plain, &out->shade_normal[0]);
    if (st == LM_OK)
        st = link(normal_vs, normal_fs_textured, &out->shade_normal[1]);
    if (st == LM_OK)
        st = link(clear_vs, clear_fs, &out->clear);
    if (st != LM_OK) {
        wk_render_programs_destroy(out);
        return st;
    }
    for (int i = 0; i < 2; i++) {
        bind_blocks(out->shade[i]);
        bind_blocks(out->shade_normal[i]);
    }
    return LM_OK;
}

void wk_render_programs_destroy(wk_render_programs *p)
{
    for (int i = 0; i < 2; i++) {
        if (p->shade[i])
            glDeleteProgram(p->shade[i]);
        if (p->shade_normal[i])
            glDeleteProgram(p->shade_normal[i]);
        p->shade[i] = p->shade_normal[i] = 0;
    }
    if (p->clear)
        glDeleteProgram(p->clear);
    p->clear = 0;
}
