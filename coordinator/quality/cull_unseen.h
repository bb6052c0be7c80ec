/* coordinator/quality/cull_unseen.h — `--cull-unseen`: remove from a result the triangles that no
 * view of the command sees. Visibility is the CPU rasteriser's (exact, the same bits on every
 * machine, whatever --device renders the job): a triangle is seen when it is the nearest surface
 * at the centre of at least one pixel of one view, with the views rendered CO_CULL_SCALE times
 * larger than the command's images (at most LM_MAX_VIEW_SIZE), so that thin slivers a view shows
 * only between pixel centres are kept. Vertices and wedges no kept triangle uses go too; parts,
 * materials and textures stay as they are. */
#ifndef LM_COORDINATOR_QUALITY_CULL_UNSEEN_H
#define LM_COORDINATOR_QUALITY_CULL_UNSEEN_H

#include <stdint.h>

#include "common/mesh.h"
#include "common/view.h"

#define CO_CULL_SCALE 4

/* The side of the views culling renders for a command's `size`. */
int co_cull_size(int size);

/* Remove from m the triangles no view of `spec` sees (the views framed by `framing`, the
 * command's original, at co_cull_size(size)), then compact m. *removed (may be NULL) gets how many
 * triangles went. A mesh every triangle of which is unseen is refused (LM_E_INVALID): the views
 * miss the model. */
lm_status co_cull_unseen(lm_mesh *m, const lm_mesh *framing, const lm_view_spec *spec, int size,
                         uint32_t *removed);

#endif
