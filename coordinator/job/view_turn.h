/* coordinator/job/view_turn.h — other view sets of the job's distribution: the job's views turned
 * about the model's centre by a rotation drawn from (seed, stream) alone, so that they are the same
 * on any machine and for any number of workers. The validation views (`optimize --validate-every`)
 * are stream CO_VIEW_TURN_VALIDATION; the training views after the n-th plateau are stream n.
 *   sphere   a uniform random rotation (Shoemake's quaternion): the same placement, turned
 *            anywhere, so no view coincides with a training, held-out or dense view;
 *   upper    a turn about +Y by a uniform angle: the set stays in the upper hemisphere;
 *   cameras  a turn of every camera about +Y through the centre by a uniform angle within
 *            ±CO_VIEW_TURN_CAMERA_DEG: viewpoints next to the user's, at their heights, distances
 *            and fields of view (no wider set of unseen cameras follows from a list of cameras). */
#ifndef LM_COORDINATOR_JOB_VIEW_TURN_H
#define LM_COORDINATOR_JOB_VIEW_TURN_H

#include <stdint.h>

#include "common/view.h"

#define CO_VIEW_TURN_VALIDATION 0xffffffffu
#define CO_VIEW_TURN_CAMERA_DEG 15.0

/* The rotation (row-major 3x3) of stream `stream` for views of distribution `dist`. */
void co_view_turn_matrix(lm_view_dist dist, uint64_t seed, uint32_t stream, double r[9]);

/* Turn every view of s by stream `stream`'s rotation about centre (stream 0: nothing, the set as
 * made). */
void co_view_turn_apply(lm_view_set *s, lm_view_dist dist, uint64_t seed, uint32_t stream,
                        const float centre[3]);

#endif
