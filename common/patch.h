/* common/patch.h — what the views need to know of a mesh change: triangles removed (by id) and
 * triangles added (id + full per-corner data). This is the narrow, self-contained record that the
 * renderer's replica applies and that the wire protocol will carry to worker processes: the views
 * never see the mesh's topology. A "move" T -> T' is one patch; an id may be both removed and
 * added (a triangle whose vertices moved). */
#ifndef LM_COMMON_PATCH_H
#define LM_COMMON_PATCH_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/mesh.h"

typedef struct lm_corner {
    float pos[3];
    float normal[3];
    float uv[2];
    float color[4];
} lm_corner;

typedef struct lm_tri_data {
    uint32_t id;
    uint32_t material;
    lm_corner c[3];
} lm_tri_data;

typedef struct lm_patch {
    uint32_t n_removed, cap_removed;
    uint32_t *removed; /* ids of triangles whose old data goes away */
    uint32_t n_added, cap_added;
    lm_tri_data *added; /* new data (ids may repeat removed ones) */
} lm_patch;

/* Fill one record from an alive triangle of the mesh. */
void lm_tri_data_from_mesh(const lm_mesh *m, uint32_t t, lm_tri_data *out);

/* All alive triangles of a mesh, in id order. Caller frees *out with free(). */
lm_status lm_mesh_export_tris(const lm_mesh *m, lm_tri_data **out, size_t *count);

void lm_patch_init(lm_patch *p);
void lm_patch_reset(lm_patch *p); /* empty, keep capacity */
void lm_patch_free(lm_patch *p);
lm_status lm_patch_remove(lm_patch *p, uint32_t id);
lm_status lm_patch_add(lm_patch *p, const lm_tri_data *t);
/* removed := ids; added := current mesh data of each alive id in `now` (sorted, deduplicated). */
lm_status lm_patch_build(lm_patch *p, const lm_mesh *m, const uint32_t *before, size_t n_before,
                         const uint32_t *now, size_t n_now);

/* The patch from the mesh as it was at journal position `mark` to the mesh now: every triangle
 * the steps after mark touched, directly or through one of its vertices or wedges (removed: those
 * that existed then; added: those alive now, with their data now). */
typedef struct lm_journal lm_journal;
lm_status lm_patch_from_journal(lm_patch *p, const lm_mesh *m, const lm_journal *j, size_t mark);

#endif
