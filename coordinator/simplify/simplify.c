/* coordinator/simplify/simplify.c — co_simplify(): argument checks, the cases no simplifier is
 * needed for (target at or above the model's size: a compact copy; targets below 4), dispatch to
 * QEM or clustering, and the helpers both simplifiers share to build their compact output meshes.
 */
#include "coordinator/simplify/simplify.h"

#include <stdlib.h>
#include <string.h>

#include "common/mesh_topology.h"
#include "coordinator/simplify/simplify_internal.h"

int co_simplify_within(uint32_t live, uint32_t target)
{
    double d = (double)live - (double)target;
    return (d < 0 ? -d : d) <= CO_SIMPLIFY_TOLERANCE * (double)target;
}

int co_simplify_reached(uint32_t live, uint32_t target)
{
    return (double)live <= (1.0 + CO_SIMPLIFY_TOLERANCE) * (double)target;
}

lm_status co_simplify_copy_materials(const lm_mesh *src, lm_mesh *dst)
{
    for (uint32_t i = 0; i < src->n_materials; i++) {
        const lm_material *mat = &src->materials[i];
        lm_image *tex = NULL;
        lm_status s = LM_OK;
        if (mat->texture)
            s = lm_image_clone(mat->texture, &tex);
        if (!s)
            s = lm_mesh_add_material(dst, mat->name, mat->diffuse, mat->texture_path, tex, NULL);
        if (s) {
            lm_image_destroy(tex);
            return s;
        }
    }
    return LM_OK;
}

lm_status co_simplify_finish(lm_mesh **m)
{
    lm_status s = lm_mesh_validate(*m);
    if (!s)
        s = lm_mesh_build_adjacency(*m);
    if (s) {
        lm_mesh_destroy(*m);
        *m = NULL;
    }
    return s;
}

/* Map every input vertex and wedge used by `tris` to a new id (ascending); LM_NONE if unused. */
static void mark_used(const lm_mesh *in, const lm_tri *tris, size_t n, uint32_t *vmap,
                      uint32_t *wmap)
{
    for (uint32_t v = 0; v < in->n_verts; v++)
        vmap[v] = LM_NONE;
    for (uint32_t w = 0; w < in->n_wedges; w++)
        wmap[w] = LM_NONE;
    for (size_t t = 0; t < n; t++)
        for (int k = 0; k < 3; k++) {
            wmap[tris[t].w[k]] = 0;
            vmap[in->wedges[tris[t].w[k]].vertex] = 0;
        }
}

static lm_status add_used(const lm_mesh *in, uint32_t *vmap, uint32_t *wmap, lm_mesh *m)
{
    lm_status s = LM_OK;
    for (uint32_t v = 0; v < in->n_verts && !s; v++)
        if (vmap[v] != LM_NONE)
            s = lm_mesh_add_vertex(m, in->pos[v], &vmap[v]);
    for (uint32_t w = 0; w < in->n_wedges && !s; w++) {
        if (wmap[w] == LM_NONE)
            continue;
        lm_wedge wd = in->wedges[w];
        wd.vertex = vmap[wd.vertex];
        s = lm_mesh_add_wedge(m, &wd, &wmap[w]);
    }
    return s;
}

static int repeats_vertex(const lm_mesh *in, const lm_tri *t)
{
    uint32_t a = in->wedges[t->w[0]].vertex, b = in->wedges[t->w[1]].vertex;
    uint32_t c = in->wedges[t->w[2]].vertex;
    return a == b || b == c || a == c;
}

lm_status co_simplify_build_from_tris(const lm_mesh *in, const lm_tri *tris, size_t n,
                                      uint32_t *dropped, lm_mesh **out)
{
    *out = NULL;
    uint32_t *vmap = malloc(((size_t)in->n_verts + 1) * sizeof *vmap);
    uint32_t *wmap = malloc(((size_t)in->n_wedges + 1) * sizeof *wmap);
    lm_mesh *m = NULL;
    lm_status s = (vmap && wmap) ? lm_mesh_create(&m) : lm_fail(LM_E_NOMEM, "out of memory");
    uint32_t drop = 0;
    if (!s) {
        m->attrs = in->attrs;
        mark_used(in, tris, n, vmap, wmap);
        s = co_simplify_copy_materials(in, m);
    }
    if (!s)
        s = lm_mesh_copy_parts(in, m);
    if (!s)
        s = add_used(in, vmap, wmap, m);
    for (size_t t = 0; t < n && !s; t++) {
        if (repeats_vertex(in, &tris[t])) {
            drop++;
            continue;
        }
        uint32_t w[3] = {wmap[tris[t].w[0]], wmap[tris[t].w[1]], wmap[tris[t].w[2]]}, id = 0;
        s = lm_mesh_add_tri(m, w, tris[t].material, &id);
        if (!s)
            m->tris[id].part = tris[t].part;
    }
    free(vmap);
    free(wmap);
    if (dropped)
        *dropped = drop;
    if (!s && drop) {
        /* Vertices used only by dropped triangles must go too: rebuild without them. */
        lm_mesh *again = NULL;
        s = co_simplify_build_from_tris(m, m->tris, m->n_tris, NULL, &again);
        lm_mesh_destroy(m);
        m = again;
    } else if (!s) {
        s = co_simplify_finish(&m);
    }
    if (s) {
        lm_mesh_destroy(m);
        return s;
    }
    *out = m;
    return LM_OK;
}

/* The model is already at (or below) the target: a compact copy is the answer. */
static lm_status copy_whole(const lm_mesh *in, lm_mesh **out)
{
    lm_tri *tris = malloc(((size_t)in->live_tris + 1) * sizeof *tris);
    if (!tris)
        return lm_fail(LM_E_NOMEM, "out of memory copying a mesh of %u triangles", in->live_tris);
    size_t n = 0;
    for (uint32_t t = 0; t < in->n_tris; t++)
        if (in->tri_alive[t])
            tris[n++] = in->tris[t];
    lm_status s = co_simplify_build_from_tris(in, tris, n, NULL, out);
    free(tris);
    return s;
}

lm_status co_simplify(const lm_mesh *in, co_simplify_method method, uint32_t target_verts,
                      lm_mesh **out)
{
    if (!out)
        return lm_fail(LM_E_INVALID, "co_simplify: no output pointer");
    *out = NULL;
    if (!in || in->live_tris == 0)
        return lm_fail(LM_E_INVALID, "co_simplify: the input mesh has no triangles");
    if (method != CO_SIMPLIFY_QEM && method != CO_SIMPLIFY_CLUSTER)
        return lm_fail(LM_E_INVALID, "co_simplify: unknown method %d", (int)method);
    lm_status s = lm_mesh_validate(in);
    if (s)
        return s;
    if (target_verts >= in->live_verts)
        return copy_whole(in, out);
    uint32_t aim = target_verts < 4 ? 4 : target_verts;
    s = method == CO_SIMPLIFY_QEM ? co_simplify_qem(in, aim, NULL, out)
                                  : co_simplify_cluster(in, aim, NULL, out);
    if (target_verts < 4 && *out && !co_simplify_reached((*out)->live_verts, target_verts))
        return lm_fail(LM_E_RANGE, "a target of %u vertices is below the minimum of 4 (best: %u)",
                       target_verts, (*out)->live_verts);
    return s;
}

lm_status co_simplify_best(const lm_mesh *in, co_simplify_method method, uint32_t target_verts,
                           lm_mesh **out, int *short_of)
{
    lm_status st = co_simplify(in, method, target_verts, out);
    *short_of = st == LM_E_RANGE && *out;
    if (*short_of)
        return LM_OK;
    if (st != LM_OK && *out) {
        lm_mesh_destroy(*out);
        *out = NULL;
    }
    return st;
}
