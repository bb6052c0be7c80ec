/* common/simplify.h — initial simplifiers that make the coarse mesh M: QEM through meshoptimizer
 * (attribute-aware where the library allows, UV seams preserved) and Rossignac–Borrel vertex
 * clustering (the paper's Figure 7a input). The result keeps materials and attributes. */
#ifndef LM_COMMON_SIMPLIFY_H
#define LM_COMMON_SIMPLIFY_H

#include "common/mesh.h"

typedef enum lm_simplify_method { LM_SIMPLIFY_QEM, LM_SIMPLIFY_CLUSTER } lm_simplify_method;

/* Aim for target_verts live vertices; succeeds when within 5%, otherwise returns LM_E_RANGE with a
 * message saying why (e.g. the model has fewer vertices, or topology stops the simplifier) while
 * still returning the best mesh through *out. */
lm_status lm_simplify(const lm_mesh *in, lm_simplify_method method, uint32_t target_verts,
                      lm_mesh **out);

#endif
