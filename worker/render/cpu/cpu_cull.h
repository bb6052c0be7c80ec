/* worker/render/cpu/cpu_cull.h — whether a set of triangles can show in a view at all, from the box
 * of their corners: the box's corners projected (every point of the box lies in their convex hull
 * on the screen, and no nearer than the nearest of them: window depth grows with eye depth), then
 * the view's depth-tile maxima over the pixels it may reach. Saves a patch's setups in the views
 * where it lies behind the visible surface. */
#ifndef LM_WORKER_CPU_CULL_H
#define LM_WORKER_CPU_CULL_H

#include <stddef.h>

#include "common/patch.h"
#include "worker/render/cpu/cpu_raster.h"

typedef struct wk_cpu_box {
    double lo[3], hi[3];
    int empty;
} wk_cpu_box;

/* An empty box, and the box grown by triangle t's corners (non-finite ones make it unbounded). */
void wk_cpu_box_clear(wk_cpu_box *b);
void wk_cpu_box_add(wk_cpu_box *b, const lm_tri_data *t);

/* 1 when no point of the box can be drawn in front of the keys k (their tile maxima) in view v:
 * every tile the box may reach lies nearer than the box's nearest corner, or it reaches none.
 * 0 when that is not certain (corners outside the depth range, no tile maxima, ...). */
int wk_cpu_box_hidden(const wk_cpu_box *b, const wk_cpu_view *v, const wk_cpu_keys *k);

#endif
