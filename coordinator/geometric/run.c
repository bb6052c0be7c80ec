/* coordinator/geometric/run.c — the geometric energy as a command (see run.h): defaults resolved
 * here (target, c_rep, seed), the phase meter fed from the optimization's progress, output
 * written with the normals recomputed from the new geometry. */
#include "coordinator/geometric/run.h"

#include <inttypes.h>
#include <stdio.h>
#include <unistd.h>

#include "common/io/mesh_io.h"
#include "coordinator/quality/phase_meter.h"

#define MIN_TARGET 100u /* as the image job's CO_JOB_MIN_TARGET_VERTS */

static void on_progress(void *ctx, const char *phase, uint64_t done, uint64_t total)
{
    co_meter *m = ctx;
    if (phase)
        co_meter_phase(m, "%s", phase);
    else
        co_meter_show(m, "edges tried", done, total, 0);
}

static lm_status resolve_target(const co_geo_run_options *o, const lm_mesh *orig, uint32_t *t)
{
    uint32_t live = orig->live_verts;
    *t = o->target_verts;
    if (!*t) {
        *t = live / 100 < MIN_TARGET ? MIN_TARGET : live / 100;
        if (*t > live / 2)
            *t = live / 2;
    }
    if (*t < 4 || *t >= live)
        return lm_fail(LM_E_RANGE,
                       "--target-verts %" PRIu32 " must be in 4..%" PRIu32
                       " (below the original's %" PRIu32 " vertices)",
                       *t, live - 1, live);
    return LM_OK;
}

static void report(const co_geo_run_options *o, const co_geo_summary *s)
{
    if (o->json) {
        printf("{\"type\":\"%s\",\"energy\":\"geometric\",\"start_verts\":%" PRIu32
               ",\"verts\":%" PRIu32 ",\"points\":%" PRIu32
               ",\"e_start\":%.9g,\"e_dist\":%.9g,\"e_spring\":%.9g,\"e_rep\":%.9g,\"e_total\":%."
               "9g,\"c_rep_final\":%.9g,\"tried\":%" PRIu64 ",\"accepted\":%" PRIu64
               ",\"collapses\":%" PRIu64 ",\"swaps\":%" PRIu64 ",\"splits\":%" PRIu64
               ",\"seconds\":%.3f}\n",
               o->then_image ? "geometric" : "summary", s->start_verts, s->verts, s->points,
               s->e_start, s->e_dist, s->e_spring, s->e_rep, s->e_total, s->c_rep_final, s->tried,
               s->accepted, s->collapses, s->swaps, s->splits, s->seconds);
        fflush(stdout);
        return;
    }
    fprintf(stderr,
            "lumesh optimize: geometric: %" PRIu32 " -> %" PRIu32 " vertices, E_dist %.4g, "
            "E %.4g (c_rep %g at the end), %" PRIu64 " of %" PRIu64 " moves kept (%" PRIu64
            " collapses, %" PRIu64 " swaps, %" PRIu64 " splits), %.1f s\n",
            s->start_verts, s->verts, s->e_dist, s->e_total, s->c_rep_final, s->accepted, s->tried,
            s->collapses, s->swaps, s->splits, s->seconds);
}

static lm_status run(const co_geo_run_options *o, co_meter *meter, co_geo_summary *sum)
{
    lm_mesh *orig = NULL, *start = NULL;
    co_meter_phase(meter, "loading %s", o->original_path);
    lm_status st = lm_mesh_load(o->original_path, NULL, &orig);
    co_meter_end(meter);
    uint32_t target = 0;
    if (st == LM_OK)
        st = resolve_target(o, orig, &target);
    if (st == LM_OK) {
        co_meter_phase(meter, "start for %" PRIu32 " vertices", target);
        st = co_geo_make_start(orig, target, o->start_multiple, &start);
        co_meter_end(meter);
    }
    if (st == LM_OK && o->initial_output_path)
        st = lm_mesh_save(o->initial_output_path, start);
    co_geo_options go = {.target_verts = target,
                         .c_rep = o->c_rep > 0 ? o->c_rep : CO_GEO_DEFAULT_C_REP,
                         .improvements = o->improvements,
                         .seed = o->seed ? o->seed : 1,
                         .on_progress = on_progress,
                         .ctx = meter};
    if (st == LM_OK)
        st = co_geo_optimize(orig, start, &go, sum);
    co_meter_end(meter);
    if (st == LM_OK)
        st = lm_mesh_compact(start);
    if (st == LM_OK) {
        lm_mesh_compute_normals(start);
        st = lm_mesh_save(o->output_path, start);
    }
    if (st == LM_OK)
        report(o, sum);
    lm_mesh_destroy(start);
    lm_mesh_destroy(orig);
    return st;
}

lm_status co_geo_run(const co_geo_run_options *o, co_geo_summary *sum)
{
    co_meter meter;
    FILE *out = o->json ? stdout : stderr;
    co_meter_style style = o->json                  ? CO_METER_JSON
                           : isatty(fileno(stderr)) ? CO_METER_TTY
                                                    : CO_METER_LINES;
    co_meter_init(&meter, "lumesh optimize", style, out);
    co_meter_stage(&meter, "geometric");
    lm_status st = run(o, &meter, sum);
    co_meter_destroy(&meter);
    return st;
}
