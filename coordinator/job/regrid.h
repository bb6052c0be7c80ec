/* coordinator/job/regrid.h — the training views' pixel grid, moved every so many evaluations
 * (`optimize --regrid-every N`). Draw 0 is the view set as made; every later draw shifts each
 * view's picture by its own offset of under a pixel, so that the optimizer cannot place edges and
 * silhouettes to cover or miss one fixed set of pixel centres, a gain no other sampling of the
 * same sights keeps (coordinator/OPTIMIZER.md, eighth and ninth rounds). The offsets are a
 * function of (seed, draw, view) alone: the same on any machine and for any number of workers. */
#ifndef LM_COORDINATOR_JOB_REGRID_H
#define LM_COORDINATOR_JOB_REGRID_H

#include <stdint.h>

#include "common/view.h"

/* The draw in force after `evals` evaluations with a new one every `every` (0 = never: 0). */
uint32_t co_regrid_draw(uint64_t evals, uint64_t every);

/* The evaluation count at which the draw after `draw` begins (UINT64_MAX with every 0). */
uint64_t co_regrid_next(uint32_t draw, uint64_t every);

/* The offset of view `view` in draw `draw`, in pixels, each in [-1/2, 1/2): (0, 0) for draw 0.
 * Over the draws each view's offsets follow a low-discrepancy (R2) sequence from a start drawn
 * from (seed, view), so that a few draws already spread over the pixel. */
void co_regrid_offset(uint64_t seed, uint32_t draw, uint32_t view, double off[2]);

/* Shift every view of s by its offset in draw `draw` (nothing for draw 0). */
void co_regrid_apply(lm_view_set *s, uint64_t seed, uint32_t draw);

#endif
