/* coordinator/simplify/lod_manifest.h — a level-of-detail set measured and described: every level
 * against the ORIGINAL (the symmetric surface distance and the image energy over the 24 held-out
 * views, as `lumesh energy --heldout --distance` measures the level's file), the switch distances
 * for a screen, and the manifest (lods.json) that says it all, written atomically.
 *
 * Switching. A world-space error e seen from distance d on a screen H pixels high with a vertical
 * field of view fov covers
 *     pixels(d) = e * H / (2 d tan(fov/2)),
 * so a level whose error is e may be shown from
 *     d_switch = e * H / (2 tan(fov/2) P)
 * on, where P is the error in pixels allowed. e is the level's maximum (sampled Hausdorff) distance
 * to the original, made a running maximum down the chain (each level is measured against the
 * original, not against the level before it), so that the switch distances never decrease.
 * screen_error_px = e * H / diagonal: the pixels e covers when the original's bounding-box
 * diagonal spans the screen height. */
#ifndef LM_COORDINATOR_SIMPLIFY_LOD_MANIFEST_H
#define LM_COORDINATOR_SIMPLIFY_LOD_MANIFEST_H

#include <stddef.h>

#include "coordinator/simplify/lod.h"

/* Measure every level into sum->level[k].m: from its file when the levels went one to a file,
 * else (one GLB) in memory; o resolved (co_lod_resolve). */
lm_status co_lod_measure_levels(const co_lod_options *o, co_lod_summary *sum,
                                const lm_mesh *const *levels);

/* The switch errors and distances of the measured levels (the formula above). */
void co_lod_switch_distances(const co_lod_options *o, co_lod_summary *sum);

/* Where the manifest goes: o->manifest_path, else lods.json in the folder of o->output_path. */
void co_lod_manifest_path(const co_lod_options *o, char *buf, size_t cap);

/* Write the manifest (atomically) to co_lod_manifest_path; its path in sum->manifest. */
lm_status co_lod_manifest_write(const co_lod_options *o, co_lod_summary *sum);

#endif
