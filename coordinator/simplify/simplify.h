/* coordinator/simplify/simplify.h — initial simplifiers that make the coarse mesh M: QEM through
 * meshoptimizer (attribute-aware where the library allows, UV seams preserved), Rossignac–Borrel
 * vertex clustering (the paper's Figure 7a input) and Park, Lee & Lee's shape-adaptive
 * simplification (adaptive.h). The result keeps materials and attributes. */
#ifndef LM_COMMON_SIMPLIFY_H
#define LM_COMMON_SIMPLIFY_H

#include "common/mesh.h"

/* CO_SIMPLIFY_ADAPTIVE: Park, Lee & Lee's shape-adaptive simplification (adaptive.h), its
 * tolerance searched for the target, which it then meets exactly where it can. */
typedef enum co_simplify_method {
    CO_SIMPLIFY_QEM,
    CO_SIMPLIFY_CLUSTER,
    CO_SIMPLIFY_ADAPTIVE
} co_simplify_method;

/* At most target_verts live vertices (an upper bound, as meshoptimizer and gltfpack treat it; the
 * searches aim within 5% of it and a result up to 5% above meets it). A model already at or below
 * the target comes back as a compact copy (LM_OK). When the target cannot be reached, LM_E_RANGE
 * with a message saying why (topology stops the simplifier) and the best mesh reached in *out;
 * any other error leaves *out NULL. */
lm_status co_simplify(const lm_mesh *in, co_simplify_method method, uint32_t target_verts,
                      lm_mesh **out);
/* co_simplify that settles for the best mesh reached: LM_OK with *short_of 1 where the target
 * could not be reached (why, in lm_last_error(), for a warning; the caller clears it), 0 where it
 * was. Any other error as co_simplify's. */
lm_status co_simplify_best(const lm_mesh *in, co_simplify_method method, uint32_t target_verts,
                           lm_mesh **out, int *short_of);

/* The parts of `in` (by name) that hold triangles there and none in `out`, as "A, B, C" in buf
 * (cap bytes, cut with "..." when long); returns how many. 0 where `in` has no part table. */
uint32_t co_simplify_lost_parts(const lm_mesh *in, const lm_mesh *out, char *buf, size_t cap);
/* One warning line on stderr naming the parts `out` lost ("lumesh CMD: warning: ..."), if any. */
void co_simplify_warn_lost_parts(const char *cmd, const lm_mesh *in, const lm_mesh *out);

#endif
