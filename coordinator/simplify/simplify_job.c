/* coordinator/simplify/simplify_job.c — load → QEM when large → working mesh → views (with the
 * geometric term when asked) → collapses (with the progressive mesh recorded) → output and
 * progressive mesh written; and the same middle part on a model in memory (co_simplify_mesh). */
#include "coordinator/simplify/simplify_job.h"
#include "coordinator/quality/cull_unseen.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/folders.h"
#include "common/io/mesh_io.h"
#include "common/optimizer/surface_term.h"
#include "coordinator/pool/pool.h"
#include "coordinator/quality/view_setup.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/simplify/work.h"

typedef struct sjob {
    const co_simplify_options *o;
    co_simplify_summary *sum;
    const lm_mesh *in;
    lm_mesh *own_in, *ref, *work;
    lm_view_set *vs;
    co_pool *pool, *own_pool;      /* pool: own_pool, or the caller's */
    lm_views *views, *image_views; /* views: image_views, or the geometric term over them */
    co_pm_recorder *rec;
    int derived;
    co_meter *meter, own_meter; /* meter: the caller's, or own_meter */
} sjob;

/* The caller's meter, or one of this command's own. */
static void meter_start(sjob *j)
{
    j->meter = j->o->meter;
    if (!j->meter) {
        co_meter_init(&j->own_meter, "lumesh simplify", j->o->progress, stderr);
        j->meter = &j->own_meter;
    }
}

static lm_status load(sjob *j)
{
    co_meter_phase(j->meter, "loading %s", j->o->input_path);
    lm_status st = lm_mesh_load(j->o->input_path, NULL, &j->own_in);
    co_meter_end(j->meter);
    j->in = j->own_in;
    if (st == LM_OK && j->o->reference_path)
        st = lm_mesh_load(j->o->reference_path, NULL, &j->ref);
    if (st == LM_OK) {
        j->sum->in_verts = j->in->live_verts;
        j->sum->in_tris = j->in->live_tris;
    }
    return st;
}

/* QEM to the start size when the model is larger (its best mesh when QEM stops short). */
static lm_status start_mesh(sjob *j)
{
    uint32_t start =
        co_simplify_start_verts(j->in->live_verts, j->o->target_verts, j->o->presimplify);
    lm_status st;
    if (start < j->in->live_verts) {
        int short_of;
        co_meter_phase(j->meter, "QEM to %u vertices", start);
        st = co_simplify_best(j->in, CO_SIMPLIFY_QEM, start, &j->work, &short_of);
        co_meter_end(j->meter);
        if (short_of)
            lm_clear_error();
    } else {
        st = lm_mesh_clone(j->in, &j->work);
    }
    if (st == LM_OK)
        st = co_simplify_prepare(j->work, &j->derived);
    if (st == LM_OK)
        j->sum->start_verts = j->work->live_verts;
    return st;
}

/* The weight surface_share gives: E_geo that share of the image energy of QEM's mesh at the
 * target, with the term (at weight 1) over the views; the views are left on that mesh. */
static lm_status share_weight(sjob *j, double *w)
{
    lm_mesh *qem = NULL;
    int derived;
    int short_of;
    lm_status st = co_simplify_best(j->in, CO_SIMPLIFY_QEM, j->o->target_verts, &qem, &short_of);
    if (short_of)
        lm_clear_error();
    if (st == LM_OK)
        st = co_simplify_prepare(qem, &derived);
    if (st == LM_OK)
        st = lm_views_set_mesh_from(j->views, qem);
    if (st == LM_OK)
        st = lm_surface_views_weight_for_share(j->views, j->o->surface_share, w);
    lm_mesh_destroy(qem);
    return st;
}

/* The geometric term over the image views: every collapse is priced by ΔE_image + ΔE_geo. */
static lm_status wrap_surface(sjob *j, const lm_mesh *ref)
{
    double w = j->o->surface_weight > 0 ? j->o->surface_weight : 1.0;
    j->image_views = j->views;
    j->views = NULL;
    lm_status st = lm_surface_views_create(j->image_views, ref, w, &j->views);
    if (st == LM_OK && !(j->o->surface_weight > 0)) {
        st = share_weight(j, &w);
        if (st == LM_OK)
            st = lm_surface_views_set_weight(j->views, w);
    }
    j->sum->surface_weight = w;
    return st == LM_OK ? lm_views_set_mesh_from(j->views, j->work) : st;
}

static lm_status make_views(sjob *j)
{
    const lm_mesh *ref = j->ref ? j->ref : j->in;
    int size = j->o->size ? j->o->size : LM_DEFAULT_VIEW_SIZE;
    lm_status st = co_view_set_of(ref, &j->o->views, size, 0, &j->vs);
    if (st == LM_OK && j->o->method == CO_PRICE_IMAGE && !j->pool) {
        st = co_simplify_pool_start(&j->o->workers, j->o->device, &j->own_pool);
        j->pool = j->own_pool;
    }
    co_meter_phase(j->meter, "the original's target images (%u views of %dx%d)",
                   st == LM_OK ? j->vs->count : 0, size, size);
    if (st == LM_OK)
        st = co_simplify_make_views(j->o->method, ref, j->work, j->vs, j->o->device, j->pool,
                                    &j->views);
    co_meter_end(j->meter);
    if (st == LM_OK && j->o->method == CO_PRICE_IMAGE &&
        (j->o->surface_weight > 0 || j->o->surface_share > 0)) {
        co_meter_phase(j->meter, "the geometric term (its weight: QEM to %u vertices)",
                       j->o->target_verts);
        st = wrap_surface(j, ref);
        co_meter_end(j->meter);
    }
    if (st == LM_OK) {
        lm_views_info info;
        j->views->ops->info(j->views, &info);
        snprintf(j->sum->renderer, sizeof j->sum->renderer, "%s", info.renderer);
    }
    return st;
}

/* Signals caught by a caller (the optimize job) stop the simplification at its next step. */
static lm_status stop_if_interrupted(void)
{
    if (!co_pool_interrupted())
        return LM_OK;
    return lm_fail(
        LM_E_INVALID,
        "interrupted (signal %d) during the image-driven simplification: nothing written",
        co_pool_interrupt_signal());
}

static lm_status on_step(void *ctx, const lm_mesh *m, co_isimp_step *s)
{
    sjob *j = ctx;
    lm_status st = stop_if_interrupted();
    if (st != LM_OK)
        return st;
    if (s->index == 0)
        co_meter_phase(j->meter, "collapses");
    uint32_t start = j->sum->start_verts, target = j->o->target_verts;
    char what[64];
    snprintf(what, sizeof what, "%u vertices, %" PRIu64 " evaluations", m->live_verts,
             s->evaluations);
    co_meter_show(j->meter, what, s->index + 1U, start > target ? start - target : 0,
                  m->live_verts <= target);
    return j->rec && s->split ? co_pm_recorder_take(j->rec, s->split) : LM_OK;
}

static lm_status on_priced(void *ctx, uint32_t done, uint32_t total)
{
    sjob *j = ctx;
    co_meter_show(j->meter, NULL, done, total, done == total);
    return stop_if_interrupted();
}

static lm_status simplify(sjob *j)
{
    lm_status st = j->o->pm_path ? co_pm_recorder_create(&j->rec) : LM_OK;
    co_isimp_config cfg = {.method = j->o->method,
                           .target_verts = j->o->target_verts,
                           .views = j->vs,
                           .derived_normals = j->derived,
                           .record_splits = j->rec != NULL,
                           .on_step = on_step,
                           .on_priced = on_priced,
                           .ctx = j};
    co_meter_phase(j->meter, "pricing every edge");
    if (st == LM_OK)
        st = co_isimp_run(j->work, j->views, &cfg, &j->sum->stats);
    co_meter_end(j->meter);
    return st;
}

static lm_status write_outputs(sjob *j)
{
    lm_mesh *out = NULL;
    lm_status st = lm_make_parent_folders(j->o->output_path);
    if (st == LM_OK && j->o->pm_path)
        st = lm_make_parent_folders(j->o->pm_path);
    if (st == LM_OK)
        st = co_simplify_output_copy(j->work, &out);
    if (st == LM_OK && j->o->cull_unseen) {
        co_meter_phase(j->meter, "triangles no view sees");
        st = co_cull_unseen(out, j->ref ? j->ref : j->in, &j->o->views,
                            j->o->size ? j->o->size : LM_DEFAULT_VIEW_SIZE, &j->sum->culled_tris);
    }
    co_meter_phase(j->meter, "writing %s", j->o->output_path);
    if (st == LM_OK)
        st = lm_mesh_save(j->o->output_path, out);
    if (st == LM_OK && j->o->pm_path)
        st = co_pm_write(j->o->pm_path, j->work, j->rec, j->sum->start_verts);
    co_meter_end(j->meter);
    if (st == LM_OK) {
        j->sum->out_verts = out->live_verts;
        j->sum->out_tris = out->live_tris;
        j->sum->out_parts = lm_mesh_count_parts(out);
        co_simplify_warn_lost_parts("simplify", j->in, out);
    }
    lm_mesh_destroy(out);
    return st;
}

/* The stages between the loaded model and the result (j->work), timed into the summary. */
static lm_status run_stages(sjob *j)
{
    double t1 = co_now_s();
    lm_status st = start_mesh(j);
    if (st == LM_OK)
        st = make_views(j);
    double t2 = co_now_s();
    if (st == LM_OK)
        st = simplify(j);
    j->sum->prepare_s = t2 - t1;
    j->sum->simplify_s = co_now_s() - t2;
    return st;
}

static void sjob_free(sjob *j)
{
    if (j->meter == &j->own_meter)
        co_meter_destroy(&j->own_meter);
    co_pm_recorder_destroy(j->rec);
    lm_views_destroy(j->views);
    lm_views_destroy(j->image_views);
    co_pool_destroy(j->own_pool);
    free(j->vs);
    lm_mesh_destroy(j->work);
    lm_mesh_destroy(j->ref);
    lm_mesh_destroy(j->own_in);
}

lm_status co_simplify_job_run(const co_simplify_options *o, co_simplify_summary *sum)
{
    memset(sum, 0, sizeof *sum);
    sjob j = {.o = o, .sum = sum};
    meter_start(&j);
    double t0 = co_now_s();
    lm_status st = load(&j);
    sum->load_s = co_now_s() - t0;
    if (st == LM_OK)
        st = run_stages(&j);
    double t3 = co_now_s();
    if (st == LM_OK)
        st = write_outputs(&j);
    sum->write_s = co_now_s() - t3;
    sjob_free(&j);
    return st;
}

lm_status co_simplify_mesh(const lm_mesh *in, const co_simplify_options *o, co_pool *pool,
                           lm_mesh **out, co_simplify_summary *sum)
{
    *out = NULL;
    memset(sum, 0, sizeof *sum);
    if (o->reference_path || o->pm_path || o->method != CO_PRICE_IMAGE)
        return lm_fail(LM_E_INVALID, "co_simplify_mesh: the image method, no reference or pm");
    sjob j = {.o = o, .sum = sum, .in = in, .pool = pool};
    meter_start(&j);
    sum->in_verts = in->live_verts;
    sum->in_tris = in->live_tris;
    lm_status st = run_stages(&j);
    if (st == LM_OK)
        st = co_simplify_output_copy(j.work, out);
    if (st == LM_OK) {
        sum->out_verts = (*out)->live_verts;
        sum->out_tris = (*out)->live_tris;
        sum->out_parts = lm_mesh_count_parts(*out);
    }
    sjob_free(&j);
    return st;
}
