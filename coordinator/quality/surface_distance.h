/* coordinator/quality/surface_distance.h — the geometric error of a model against its original:
 * the symmetric surface distance by surface sampling (as Metro does): points spread over each
 * surface in proportion to area (stratified, from a fixed seed: the same meshes give the same
 * numbers), each point's distance to the closest point of the other surface. Mean, RMS and max
 * are over both sample sets together (the max is the sampled Hausdorff distance). */
#ifndef LM_COORDINATOR_SURFACE_DISTANCE_H
#define LM_COORDINATOR_SURFACE_DISTANCE_H

#include <stdint.h>

#include "common/mesh.h"

#define CO_DISTANCE_SAMPLES 50000u /* per surface, by default */

typedef struct co_surface_distance {
    double mean, rms, max;     /* in the models' units */
    double mean_to_original;   /* one side: the model's points to the original's surface */
    double mean_from_original; /* the other: the original's points to the model's surface */
    double diagonal;           /* the original's bounding-box diagonal (the report's unit) */
    uint32_t samples;          /* points per surface */
} co_surface_distance;

/* Distances between the live triangles of `original` and `model` with `samples` points on each
 * surface (0 = CO_DISTANCE_SAMPLES). */
lm_status co_surface_distance_measure(const lm_mesh *original, const lm_mesh *model,
                                      uint32_t samples, co_surface_distance *out);

/* The points themselves (for tests): n points on m's surface, area-weighted and stratified. *out
 * is malloc'ed (3 doubles a point). */
lm_status co_surface_sample(const lm_mesh *m, uint32_t n, uint64_t seed, double **out);

#endif
