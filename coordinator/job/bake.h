/* coordinator/job/bake.h — `--bake normal` on a written result (optimize; lod's levels): the
 * original and the result loaded, a normal map baked (common/bake_normal.h) through the result's
 * texture coordinates when they can carry one, else through a per-triangle atlas
 * (common/uv_atlas.h) that replaces them, the result's colour textures resampled into it;
 * written as PNG beside the result (OUT's name without its extension + "_normal.png"), attached
 * to every material and the result saved again (GLB: normalTexture and TANGENT). */
#ifndef LM_COORDINATOR_JOB_BAKE_H
#define LM_COORDINATOR_JOB_BAKE_H

#include "common/bake_normal.h"

#define CO_BAKE_DEFAULT_SIZE 1024u
#define CO_BAKE_MIN_SIZE 16u
#define CO_BAKE_MAX_SIZE 8192u

typedef struct co_bake_result {
    char map_path[4096]; /* the PNG written */
    int atlas;           /* 1: the result's coordinates were replaced by the atlas */
    unsigned resampled;  /* colour textures resampled into the atlas */
    lm_bake_stats stats;
} co_bake_result;

/* The value of --bake: LM_OK for "normal" (the one map baked so far), else LM_E_INVALID with the
 * message. */
lm_status co_bake_parse_kind(const char *val);

/* Bakes `original` onto the file `output` (rewritten) at size x size. */
lm_status co_bake_normal_file(const char *original, const char *output, int size,
                              co_bake_result *res);

/* Prints what co_bake_normal_file did: one line, or a {"type":"bake",...} record with json. */
void co_bake_print(const co_bake_result *res, int json);

#endif
