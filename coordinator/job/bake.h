/* coordinator/job/bake.h — `--bake normal,color` on a written result (optimize; lod's levels):
 * the original and the result loaded, the maps asked for baked in one texel walk
 * (common/bake_walk.h: common/bake_normal.h, common/bake_color.h) through the result's texture
 * coordinates when they can carry one, else through a packed chart atlas (common/uv_atlas.h;
 * the per-triangle atlas where its charts do not pack) that replaces them (without a colour bake,
 * the result's colour textures resampled into it); written as PNG beside the result (OUT's name
 * without its extension + "_normal.png",
 * "_color.png"), attached to every material and the result saved again (GLB: normalTexture and
 * TANGENT; baseColorTexture with the base colour factor's RGB 1 and the vertex colours dropped,
 * since the map holds them). */
#ifndef LM_COORDINATOR_JOB_BAKE_H
#define LM_COORDINATOR_JOB_BAKE_H

#include "common/bake_walk.h"

#define CO_BAKE_DEFAULT_SIZE 1024u
#define CO_BAKE_MIN_SIZE 16u
#define CO_BAKE_MAX_SIZE 8192u

/* The maps --bake names (a bit set). */
enum { CO_BAKE_NORMAL = 1u << 0, CO_BAKE_COLOR = 1u << 1 };

typedef struct co_bake_result {
    unsigned kinds;        /* CO_BAKE_* baked */
    char map_path[4096];   /* the normal map written ("" without one) */
    char color_path[4096]; /* the colour map written ("" without one) */
    int atlas;             /* 1: the result's coordinates were replaced by an atlas */
    uint32_t charts;       /* the packed atlas's charts (0: the per-triangle atlas or none) */
    unsigned resampled;    /* colour textures resampled into the atlas */
    lm_bake_stats stats;
} co_bake_result;

/* The value of --bake: a comma-separated list of normal and color (any order, each once) into
 * *kinds; else LM_E_INVALID with the message. */
lm_status co_bake_parse_kind(const char *val, unsigned *kinds);

/* Bakes the maps `kinds` of `original` onto the file `output` (rewritten) at size x size.
 * Blocking; on failure `output` may hold the unbaked result still. */
lm_status co_bake_file(const char *original, const char *output, unsigned kinds, int size,
                       co_bake_result *res);

/* The maps `kinds` of `original` baked onto `res` (normals and an atlas's coordinates, made of
 * `from`: lm_atlas_per_triangle or lm_atlas_by_id) in memory: every material of res takes them
 * (no path; with a colour map the factor's RGB 1 and res's vertex colours white; without one and
 * with `from`, from's textures resampled into the atlas, *resampled counting them, may be NULL).
 * Blocking; stats may be NULL; LM_E_NOMEM. The bakes of the optimizer's loop (bake_loop.h). */
lm_status co_bake_attach(const lm_mesh *original, lm_mesh *res, const lm_mesh *from, unsigned kinds,
                         int size, lm_bake_stats *stats, unsigned *resampled);

/* Prints what co_bake_file did: a line a map, or a {"type":"bake",...} record with json. */
void co_bake_print(const co_bake_result *res, int json);

#endif
