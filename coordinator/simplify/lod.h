/* coordinator/simplify/lod.h — a chain of levels of detail: each level simplified from the one
 * before it (the first from the original) by image-driven collapses (or shards, or QEM) against
 * the ORIGINAL's images, then optimised by the Lindstrom–Turk optimizer against the same images
 * (one set of views for the whole chain; of the two, the level with the lower energy is kept),
 * then the next level starts from that mesh.
 * Written as one file per level (or, asked for, one GLB with MSFT_lod: LOD0 in the scene, the
 * others named by its extension), part names kept in every level, with a manifest (lods.json,
 * coordinator/simplify/lod_manifest.h): per level its size, its distance and held-out image error
 * against the original, and the switch distance for a screen. */
#ifndef LM_COORDINATOR_SIMPLIFY_LOD_H
#define LM_COORDINATOR_SIMPLIFY_LOD_H

#include <stdint.h>

#include "common/io/mesh_io.h"
#include "coordinator/quality/surface_distance.h"
#include "coordinator/simplify/pricer.h"
#include "coordinator/simplify/work.h"

/* A level asked for: a fraction of the original's vertices (percent given) or a count. */
typedef struct co_lod_spec {
    double fraction; /* > 0 when given as a percentage */
    uint32_t verts;  /* otherwise */
} co_lod_spec;

/* The defaults (resolved by co_lod_resolve, nowhere else). */
#define CO_LOD_DEFAULT_EVALS 20000ull
#define CO_LOD_DEFAULT_SEED 1ull
#define CO_LOD_DEFAULT_SCREEN_HEIGHT 1080u /* pixels */
#define CO_LOD_DEFAULT_FOV 60.0            /* degrees, vertical */
#define CO_LOD_DEFAULT_PIXEL_ERROR 1.0     /* pixels */
#define CO_LOD_MANIFEST_NAME "lods.json"   /* beside the outputs */

/* Zero means default for every field but the paths and the levels. */
typedef struct co_lod_options {
    const char *input_path, *output_path;
    co_lod_spec levels[LM_MESH_MAX_LODS];
    uint32_t n_levels;
    int qem;                /* simplify each level by QEM instead of image-driven collapses */
    int adaptive;           /* or by the shape-adaptive method (coordinator/simplify/adaptive.h) */
    co_price_method method; /* image or shard */
    uint64_t evals;         /* optimisation budget per level; 0 = 20000 */
    int no_optimize;        /* levels as simplified (no optimisation) */
    lm_view_spec views;     /* count 0 = 20; dist 0 = the sphere */
    int size;               /* 0 = 256 */
    const char *device;
    co_simplify_workers workers; /* lumesh-worker processes for the views (none: this process) */
    uint64_t seed;               /* optimizer seed; 0 = 1 */
    int msft_lod;                /* one GLB with MSFT_lod; else one file per level: STEM.lodK.EXT */
    int cull_unseen; /* each level's file without the triangles no view sees (the chain is made
                        whole; quality/cull_unseen.h) */
    int progress;    /* a line per level on stderr */
    const char *manifest_path; /* NULL: lods.json in OUT's folder */
    uint32_t screen_height;    /* the switch distances' screen: pixels high, 0 = 1080 */
    double fov_deg;            /* its vertical field of view, 0 = 60 */
    double pixel_error;        /* the error in pixels a level may show, 0 = 1 */
} co_lod_options;

/* A level measured against the ORIGINAL (as `lumesh energy --heldout --distance` measures its file)
 * and where it may be shown from (coordinator/simplify/lod_manifest.h). */
typedef struct co_lod_measure {
    co_surface_distance distance; /* symmetric surface distance to the original */
    int64_t heldout;              /* image energy over the 24 held-out views */
    double heldout_mse;           /* ... per pixel */
    double switch_error;          /* the running maximum of distance.max down the chain */
    double screen_error_px;       /* switch_error in pixels with the model filling the screen */
    double switch_distance;       /* the distance from which the level may be shown */
} co_lod_measure;

typedef struct co_lod_level_result {
    uint32_t target, verts, tris, parts;
    uint32_t collapses;
    uint64_t simplify_evals, optimize_evals;
    int64_t energy_simplified, energy_optimized; /* on the job's views */
    int kept_simplified;  /* the optimised level lost to the simplified one, which was kept */
    uint32_t culled_tris; /* triangles --cull-unseen removed from the level's file */
    double seconds;
    char path[1024]; /* the file it went to (one file per level), else "" */
    co_lod_measure m;
} co_lod_level_result;

typedef struct co_lod_summary {
    uint32_t in_verts, in_tris, n_levels;
    co_lod_level_result level[LM_MESH_MAX_LODS];
    double seconds;
    char renderer[128];
    char heldout_renderer[128]; /* what rendered the held-out views */
    uint32_t in_parts, heldout_views;
    char manifest[1024]; /* where the manifest went */
} co_lod_summary;

/* o with every default filled in (the one place they are resolved). */
co_lod_options co_lod_resolve(const co_lod_options *o);

/* Parse "50%,25%,10%" or "2000,500,100" (mixed allowed); LM_E_INVALID naming the bad item. */
lm_status co_lod_parse_levels(const char *spec, co_lod_options *o);

/* STEM.lodK.EXT for OUT = STEM.EXT (buf of cap bytes). */
void co_lod_level_path(const char *out, uint32_t k, char *buf, size_t cap);

/* The levels in memory (levels[0..n_levels), compact, owned by the caller), nothing written. */
lm_status co_lod_build(const co_lod_options *o, co_lod_summary *sum, lm_mesh **levels);
/* Build and write them, measure them and write the manifest. */
lm_status co_lod_run(const co_lod_options *o, co_lod_summary *sum);

#endif
