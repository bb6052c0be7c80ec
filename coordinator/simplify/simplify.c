/* coordinator/simplify/simplify.c — co_simplify(): argument checks, the cases no simplifier is
 * needed for (target at or above the model's size: a compact copy; targets below 4), dispatch to
 * QEM, clustering or the shape-adaptive method, the helpers both simplifiers share to build their
 * compact output meshes, and the parts a simplification lost, named for a warning. */
#include "coordinator/simplify/simplify.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh_topology.h"
#include "coordinator/simplify/adaptive.h"
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
    return lm_mesh_copy_materials(src, dst);
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

lm_status co_simplify_copy_live(const lm_mesh *in, lm_mesh **out)
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
    if (method != CO_SIMPLIFY_QEM && method != CO_SIMPLIFY_CLUSTER &&
        method != CO_SIMPLIFY_ADAPTIVE)
        return lm_fail(LM_E_INVALID, "co_simplify: unknown method %d", (int)method);
    lm_status s = lm_mesh_validate(in);
    if (s)
        return s;
    if (target_verts >= in->live_verts)
        return co_simplify_copy_live(in, out); /* already at (or below) the target */
    uint32_t aim = target_verts < 4 ? 4 : target_verts;
    if (method == CO_SIMPLIFY_ADAPTIVE)
        s = co_simplify_adaptive(in, 0, aim, NULL, out);
    else
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

/* used[p] = 1 for every part p holding a live triangle of m. */
static void parts_used(const lm_mesh *m, uint8_t *used, uint32_t n_parts)
{
    for (uint32_t t = 0; t < m->n_tris; t++)
        if (m->tri_alive[t] && m->tris[t].part < n_parts)
            used[m->tris[t].part] = 1;
}

/* Append the compact mesh `add` (same materials and parts as m) to m. */
static lm_status append_mesh(lm_mesh *m, const lm_mesh *add)
{
    uint32_t v0 = m->n_verts, w0 = m->n_wedges;
    lm_status s = LM_OK;
    for (uint32_t v = 0; v < add->n_verts && !s; v++)
        s = lm_mesh_add_vertex(m, add->pos[v], NULL);
    for (uint32_t w = 0; w < add->n_wedges && !s; w++) {
        lm_wedge wd = add->wedges[w];
        wd.vertex += v0;
        s = lm_mesh_add_wedge(m, &wd, NULL);
    }
    for (uint32_t t = 0; t < add->n_tris && !s; t++) {
        const lm_tri *tr = &add->tris[t];
        uint32_t w[3] = {tr->w[0] + w0, tr->w[1] + w0, tr->w[2] + w0}, id = 0;
        if (add->tri_alive[t] && !(s = lm_mesh_add_tri(m, w, tr->material, &id)))
            m->tris[id].part = tr->part;
    }
    return s;
}

/* Part p of `in` alone at its smallest non-empty QEM form, appended to out. */
static lm_status append_smallest_part(const lm_mesh *in, uint32_t p, lm_mesh *out)
{
    lm_tri *tris = malloc(((size_t)in->live_tris + 1) * sizeof *tris);
    if (!tris)
        return lm_fail(LM_E_NOMEM, "out of memory keeping a part");
    size_t n = 0;
    for (uint32_t t = 0; t < in->n_tris; t++)
        if (in->tri_alive[t] && in->tris[t].part == p)
            tris[n++] = in->tris[t];
    lm_mesh *part = NULL, *small = NULL;
    lm_status s = co_simplify_build_from_tris(in, tris, n, NULL, &part);
    free(tris);
    if (!s) {
        s = co_simplify_qem(part, 4, NULL, &small);
        s = s == LM_E_RANGE && small ? LM_OK : s;
    }
    if (!s)
        s = append_mesh(out, small);
    lm_mesh_destroy(part);
    lm_mesh_destroy(small);
    return s;
}

lm_status co_simplify_keep_parts(const lm_mesh *in, lm_mesh *out, uint32_t *kept)
{
    *kept = 0;
    if (in->n_parts < 2 || out->n_parts != in->n_parts)
        return LM_OK;
    uint8_t *had = calloc(in->n_parts, 1), *has = calloc(in->n_parts, 1);
    lm_status s = had && has ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory keeping parts");
    if (!s) {
        parts_used(in, had, in->n_parts);
        parts_used(out, has, in->n_parts);
    }
    for (uint32_t p = 0; !s && p < in->n_parts; p++)
        if (had[p] && !has[p]) {
            s = append_smallest_part(in, p, out);
            (*kept)++;
        }
    if (!s && *kept)
        s = lm_mesh_build_adjacency(out);
    free(had);
    free(has);
    return s;
}

uint32_t co_simplify_lost_parts(const lm_mesh *in, const lm_mesh *out, char *buf, size_t cap)
{
    uint32_t n = in->n_parts, lost = 0;
    uint8_t *had = n ? calloc(n, 1) : NULL, *has = n ? calloc(n, 1) : NULL;
    size_t len = 0;
    if (cap)
        buf[0] = 0;
    if (had && has) {
        parts_used(in, had, n);
        for (uint32_t t = 0; t < out->n_tris; t++) /* by name: ids may differ */
            if (out->tri_alive[t]) {
                uint32_t p = lm_mesh_find_part(in, lm_mesh_part_name(out, t));
                if (p != LM_NONE)
                    has[p] = 1;
            }
    }
    for (uint32_t p = 0; had && has && p < n; p++) {
        if (!had[p] || has[p])
            continue;
        if (len < cap) {
            int w = snprintf(buf + len, cap - len, "%s'%s'", lost ? ", " : "", in->parts[p].name);
            len += w > 0 ? (size_t)w : 0;
        }
        lost++;
    }
    if (len >= cap && cap > 4)
        memcpy(buf + cap - 4, "...", 4);
    free(had);
    free(has);
    return lost;
}

void co_simplify_warn_lost_parts(const char *cmd, const lm_mesh *in, const lm_mesh *out)
{
    char names[512];
    uint32_t n = co_simplify_lost_parts(in, out, names, sizeof names);
    if (n)
        fprintf(stderr, "lumesh %s: warning: the simplification removed %u part%s: %s\n", cmd, n,
                n == 1 ? "" : "s", names);
}
