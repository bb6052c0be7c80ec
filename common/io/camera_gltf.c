/* common/io/camera_gltf.c — the cameras of a glTF 2.0 file (see camera_gltf.h): the node tree
 * walked depth first with each level's world matrix (column-major, as glTF writes them), and a
 * camera made of each perspective camera node. */
#include "common/io/camera_gltf.h"

#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bytes.h"
#include "common/log.h"

#define GLB_MAGIC 0x46546C67u      /* "glTF" */
#define GLB_CHUNK_JSON 0x4E4F534Au /* "JSON" */
#define GLTF_MAX_DEPTH 1024        /* deeper node trees are refused */

int lm_gltf_is_glb(const char *bytes, size_t len)
{
    return len >= 4 && lm_le32(bytes) == GLB_MAGIC;
}

lm_status lm_gltf_json_chunk(const char *bytes, size_t len, const char *name, const char **json,
                             size_t *json_len)
{
    if (len < 20)
        return lm_fail(LM_E_FORMAT, "glTF file '%s': truncated binary header", name);
    if (lm_le32(bytes + 4) != 2)
        return lm_fail(LM_E_FORMAT, "glTF file '%s': binary glTF version %u, expected 2", name,
                       lm_le32(bytes + 4));
    uint32_t chunk = lm_le32(bytes + 12);
    if (lm_le32(bytes + 16) != GLB_CHUNK_JSON)
        return lm_fail(LM_E_FORMAT, "glTF file '%s': the first chunk is not JSON", name);
    if (chunk > len - 20)
        return lm_fail(LM_E_FORMAT, "glTF file '%s': the JSON chunk runs past the end", name);
    *json = bytes + 20;
    *json_len = chunk;
    return LM_OK;
}

typedef struct level {
    size_t node, next_child;
    double world[16];
} level;

typedef struct walk {
    json_t *nodes, *cameras;
    const char *name;
    unsigned char *seen;
    lm_camera *out;
    uint32_t n, orthographic;
    level lv[GLTF_MAX_DEPTH];
} walk;

static lm_status bad_node(const walk *w, size_t node, const char *what)
{
    return lm_fail(LM_E_FORMAT, "glTF file '%s': node %zu: %s", w->name, node, what);
}

/* A node index: an integer naming one of the nodes. */
static int node_index(const walk *w, json_t *v, size_t *out)
{
    if (!json_is_integer(v) || json_integer_value(v) < 0 ||
        (uint64_t)json_integer_value(v) >= json_array_size(w->nodes))
        return 0;
    *out = (size_t)json_integer_value(v);
    return 1;
}

/* `count` numbers of array `key` of obj into v; absent keeps v. 0 when malformed. */
static int read_numbers(json_t *obj, const char *key, size_t count, double *v)
{
    json_t *a = json_object_get(obj, key);
    if (!a)
        return 1;
    if (!json_is_array(a) || json_array_size(a) != count)
        return 0;
    for (size_t i = 0; i < count; i++) {
        json_t *x = json_array_get(a, i);
        if (!json_is_number(x))
            return 0;
        v[i] = json_number_value(x);
    }
    return 1;
}

/* The node's local matrix: "matrix", else translation * rotation * scale. 0 when malformed. */
static int local_matrix(json_t *node, double m[16])
{
    if (json_object_get(node, "matrix"))
        return read_numbers(node, "matrix", 16, m);
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (!read_numbers(node, "translation", 3, t) || !read_numbers(node, "rotation", 4, q) ||
        !read_numbers(node, "scale", 3, s))
        return 0;
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(len > 0.0) || !isfinite(len))
        return 0;
    double x = q[0] / len, y = q[1] / len, z = q[2] / len, r = q[3] / len;
    const double rot[9] = {
        /* column-major 3x3 */
        1 - 2 * (y * y + z * z), 2 * (x * y + z * r),     2 * (x * z - y * r),
        2 * (x * y - z * r),     1 - 2 * (x * x + z * z), 2 * (y * z + x * r),
        2 * (x * z + y * r),     2 * (y * z - x * r),     1 - 2 * (x * x + y * y)};
    for (int c = 0; c < 3; c++) {
        for (int k = 0; k < 3; k++)
            m[c * 4 + k] = rot[c * 3 + k] * s[c];
        m[c * 4 + 3] = 0.0;
    }
    m[12] = t[0], m[13] = t[1], m[14] = t[2], m[15] = 1.0;
    return 1;
}

static void mat4_mul(const double a[16], const double b[16], double out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double acc = 0.0;
            for (int k = 0; k < 4; k++)
                acc += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = acc;
        }
}

/* The camera of a node with world matrix m: its translation, looking down -Z, +Y up. */
static lm_status add_camera(walk *w, size_t node, json_t *index, const double m[16])
{
    json_t *cam = json_is_integer(index) && json_integer_value(index) >= 0
                      ? json_array_get(w->cameras, (size_t)json_integer_value(index))
                      : NULL;
    if (!json_is_object(cam))
        return bad_node(w, node, "\"camera\" names no camera");
    const char *type = json_string_value(json_object_get(cam, "type"));
    if (type && !strcmp(type, "orthographic")) {
        w->orthographic++;
        return LM_OK;
    }
    json_t *yfov = json_object_get(json_object_get(cam, "perspective"), "yfov");
    if (!type || strcmp(type, "perspective") || !json_is_number(yfov))
        return bad_node(w, node, "its camera is not a perspective camera with a yfov");
    if (w->n == LM_MAX_VIEWS)
        return lm_fail(LM_E_FORMAT, "glTF file '%s': more than %d cameras", w->name, LM_MAX_VIEWS);
    double fwd[3] = {-m[8], -m[9], -m[10]};
    double len = sqrt(fwd[0] * fwd[0] + fwd[1] * fwd[1] + fwd[2] * fwd[2]);
    if (!(len > 0.0) || !isfinite(len))
        return bad_node(w, node, "its transform has no view direction");
    double step = fmax(1.0, fmax(fabs(m[12]), fmax(fabs(m[13]), fabs(m[14]))));
    lm_camera *c = &w->out[w->n];
    for (int i = 0; i < 3; i++) {
        c->position[i] = (float)m[12 + i];
        c->target[i] = (float)(m[12 + i] + fwd[i] / len * step);
        c->up[i] = (float)m[4 + i];
    }
    c->fov_deg = (float)(json_number_value(yfov) * 180.0 / M_PI);
    const char *why = lm_camera_problem(c);
    if (why)
        return bad_node(w, node, why);
    w->n++;
    return LM_OK;
}

/* Make level `depth` the node's: world = parent * local; its camera if it has one. */
static lm_status enter(walk *w, int depth, size_t node, const double parent[16])
{
    if (depth >= GLTF_MAX_DEPTH)
        return bad_node(w, node, "the node tree is deeper than 1024 levels");
    if (w->seen[node])
        return bad_node(w, node, "reached twice (glTF nodes form a tree)");
    w->seen[node] = 1;
    json_t *obj = json_array_get(w->nodes, node);
    double local[16];
    if (!json_is_object(obj) || !local_matrix(obj, local))
        return bad_node(w, node, "malformed node or transform");
    level *l = &w->lv[depth];
    l->node = node;
    l->next_child = 0;
    mat4_mul(parent, local, l->world);
    json_t *camera = json_object_get(obj, "camera");
    return camera ? add_camera(w, node, camera, l->world) : LM_OK;
}

/* Depth first from root, children in their order. */
static lm_status walk_tree(walk *w, size_t root)
{
    static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    int d = 0;
    lm_status st = enter(w, 0, root, identity);
    while (st == LM_OK && d >= 0) {
        level *l = &w->lv[d];
        json_t *kids = json_object_get(json_array_get(w->nodes, l->node), "children");
        if (kids && !json_is_array(kids))
            return bad_node(w, l->node, "\"children\" is not an array");
        if (l->next_child >= json_array_size(kids)) {
            d--;
            continue;
        }
        size_t k;
        if (!node_index(w, json_array_get(kids, l->next_child++), &k))
            return bad_node(w, l->node, "a child is not a node index");
        st = enter(w, d + 1, k, l->world);
        d++;
    }
    return st;
}

/* The roots: the default scene's nodes, else every node that is no node's child. */
static lm_status walk_roots(walk *w, json_t *root)
{
    json_t *scenes = json_object_get(root, "scenes");
    if (json_array_size(scenes) > 0) {
        json_t *si = json_object_get(root, "scene");
        size_t s = si ? (size_t)json_integer_value(si) : 0;
        if ((si && (!json_is_integer(si) || json_integer_value(si) < 0)) ||
            s >= json_array_size(scenes))
            return lm_fail(LM_E_FORMAT, "glTF file '%s': \"scene\" names no scene", w->name);
        json_t *list = json_object_get(json_array_get(scenes, s), "nodes");
        lm_status st = LM_OK;
        for (size_t i = 0; st == LM_OK && i < json_array_size(list); i++) {
            size_t r;
            st = node_index(w, json_array_get(list, i), &r)
                     ? walk_tree(w, r)
                     : lm_fail(LM_E_FORMAT, "glTF file '%s': scene %zu: a node index is bad",
                               w->name, s);
        }
        return st;
    }
    size_t count = json_array_size(w->nodes);
    unsigned char *child = calloc(count ? count : 1, 1);
    if (!child)
        return lm_fail(LM_E_NOMEM, "out of memory for glTF file '%s'", w->name);
    for (size_t i = 0; i < count; i++) {
        json_t *kids = json_object_get(json_array_get(w->nodes, i), "children");
        for (size_t k = 0, c; k < json_array_size(kids); k++)
            if (node_index(w, json_array_get(kids, k), &c))
                child[c] = 1;
    }
    lm_status st = LM_OK;
    for (size_t i = 0; st == LM_OK && i < count; i++)
        if (!child[i] && !w->seen[i])
            st = walk_tree(w, i);
    free(child);
    return st;
}

lm_status lm_gltf_cameras(const void *root_, const char *name, lm_camera *out, uint32_t *n)
{
    json_t *root = (json_t *)root_;
    walk *w = calloc(1, sizeof *w);
    size_t count = json_array_size(json_object_get(root, "nodes"));
    if (w)
        w->seen = calloc(count ? count : 1, 1);
    if (!w || !w->seen) {
        if (w)
            free(w);
        return lm_fail(LM_E_NOMEM, "out of memory for glTF file '%s'", name);
    }
    w->nodes = json_object_get(root, "nodes");
    w->cameras = json_object_get(root, "cameras");
    w->name = name;
    w->out = out;
    lm_status st = walk_roots(w, root);
    if (st == LM_OK && w->n == 0)
        st = lm_fail(LM_E_FORMAT, "glTF file '%s': no perspective camera in its scene%s", name,
                     w->orthographic ? " (orthographic ones are not supported)" : "");
    else if (st == LM_OK && w->orthographic)
        lm_warn("glTF file '%s': %u orthographic camera%s left out (lumesh renders "
                "perspective views)",
                name, w->orthographic, w->orthographic == 1 ? "" : "s");
    if (st == LM_OK)
        *n = w->n;
    free(w->seen);
    free(w);
    return st;
}
