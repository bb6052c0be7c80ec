/* tests/bench/bench_renderers.c — how alike two renderers' images of one model are: MODEL's
 * views rendered by device A (default cpu, lumesh's rasteriser) and device B (default host,
 * llvmpipe), then per view the mean squared difference of the 8-bit luminance (what the energy
 * sees) and of the RGB channels, the largest luminance difference and the share of pixels more
 * than 2 levels apart; and each device's time, wall and CPU seconds of all threads, for making
 * the views object (context, programs, the target images) and for a full render of all views.
 *
 * usage: bench_renderers MODEL [--views N (20)] [--size S (256)] [--a DEVICE] [--b DEVICE]
 *        prints one JSON line per view and a summary line. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/io/mesh_io.h"
#include "common/view.h"
#include "worker/render/shared/image_store.h"
#include "worker/render/views_local.h"

typedef struct opts {
    const char *path, *a, *b;
    uint32_t views;
    int size;
} opts;

static double clock_s(clockid_t id)
{
    struct timespec t;
    clock_gettime(id, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Wall and CPU seconds (of every thread: llvmpipe's too) spent in making a views object (context,
 * programs, the target images) and in a second full render of the model (set_mesh). */
typedef struct timing {
    double create_wall, create_cpu, render_wall, render_cpu;
} timing;

static lm_status timed_create(const lm_mesh *m, const lm_view_set *vs, const char *device,
                              lm_views **out, timing *t)
{
    double w = clock_s(CLOCK_MONOTONIC), c = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    lm_status st = wk_views_local_create(m, vs, 0, 0, device, out);
    t->create_wall = clock_s(CLOCK_MONOTONIC) - w;
    t->create_cpu = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c;
    if (st != LM_OK)
        return st;
    w = clock_s(CLOCK_MONOTONIC);
    c = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    st = lm_views_set_mesh_from(*out, m);
    t->render_wall = clock_s(CLOCK_MONOTONIC) - w;
    t->render_cpu = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c;
    return st;
}

static int parse(int argc, char **argv, opts *o)
{
    *o = (opts){.a = "cpu", .b = "host", .views = 20, .size = 256};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (a[0] != '-') {
            o->path = a;
            continue;
        }
        if (!v)
            return 0;
        i++;
        if (!strcmp(a, "--views"))
            o->views = (uint32_t)atol(v);
        else if (!strcmp(a, "--size"))
            o->size = atoi(v);
        else if (!strcmp(a, "--a"))
            o->a = v;
        else if (!strcmp(a, "--b"))
            o->b = v;
        else
            return 0;
    }
    return o->path != NULL;
}

/* One view's differences between the colour images x and y (RGBA8, n pixels). */
static void compare_view(uint32_t h, const uint8_t *x, const uint8_t *y, size_t n, double *mse)
{
    double se = 0, se_rgb = 0;
    int worst = 0;
    size_t off = 0;
    for (size_t i = 0; i < n; i++) {
        int d = (int)lm_luma(x + 4 * i) - (int)lm_luma(y + 4 * i);
        se += d * d;
        worst = abs(d) > worst ? abs(d) : worst;
        off += d > 2 || d < -2;
        for (int ch = 0; ch < 3; ch++) {
            int c = (int)x[4 * i + ch] - (int)y[4 * i + ch];
            se_rgb += c * c;
        }
    }
    *mse = se / (double)n;
    printf("{\"view\": %u, \"luma_mse\": %.4f, \"rgb_mse\": %.4f, \"max_luma_diff\": %d, "
           "\"share_over_2\": %.5f}\n",
           h, *mse, se_rgb / (3.0 * (double)n), worst, (double)off / (double)n);
}

static lm_status run(const opts *o)
{
    lm_mesh *m;
    lm_status st = lm_mesh_load(o->path, NULL, &m);
    if (st)
        return st;
    float c[3], r;
    lm_mesh_bounding_sphere(m, c, &r);
    lm_view_set *vs = malloc(sizeof *vs);
    lm_views *va = NULL, *vb = NULL;
    timing ta = {0, 0, 0, 0}, tb = {0, 0, 0, 0};
    if (!(st = lm_view_set_make(vs, o->views, o->size, c, r)) &&
        !(st = timed_create(m, vs, o->a, &va, &ta)))
        st = timed_create(m, vs, o->b, &vb, &tb);
    size_t n = (size_t)o->size * o->size;
    uint8_t *x = malloc(n * 4), *y = malloc(n * 4);
    double sum = 0, worst = 0;
    for (uint32_t h = 0; !st && h < o->views; h++) {
        double mse;
        if (!(st = va->ops->read_image(va, LM_IMAGE_RGBA, h, x)) &&
            !(st = vb->ops->read_image(vb, LM_IMAGE_RGBA, h, y))) {
            compare_view(h, x, y, n, &mse);
            sum += mse;
            worst = mse > worst ? mse : worst;
        }
    }
    if (!st) {
        lm_views_info ia, ib;
        va->ops->info(va, &ia);
        vb->ops->info(vb, &ib);
        printf("{\"model\": \"%s\", \"tris\": %u, \"views\": %u, \"size\": %d, \"mean_luma_mse\": "
               "%.4f, \"max_view_luma_mse\": %.4f, \"a\": \"%s\", \"b\": \"%s\", \"a_create_s\": "
               "%.3f, \"b_create_s\": %.3f, \"a_create_cpu_s\": %.3f, \"b_create_cpu_s\": "
               "%.3f, \"a_render_s\": %.3f, \"b_render_s\": %.3f, \"a_render_cpu_s\": %.3f, "
               "\"b_render_cpu_s\": %.3f}\n",
               o->path, m->live_tris, o->views, o->size, sum / o->views, worst, ia.renderer,
               ib.renderer, ta.create_wall, tb.create_wall, ta.create_cpu, tb.create_cpu,
               ta.render_wall, tb.render_wall, ta.render_cpu, tb.render_cpu);
    }
    free(x);
    free(y);
    lm_views_destroy(va);
    lm_views_destroy(vb);
    free(vs);
    lm_mesh_destroy(m);
    return st;
}

int main(int argc, char **argv)
{
    opts o;
    if (!parse(argc, argv, &o)) {
        fprintf(stderr, "usage: bench_renderers MODEL [--views N] [--size S] [--a DEVICE] "
                        "[--b DEVICE]\n");
        return 1;
    }
    lm_status st = run(&o);
    if (st) {
        fprintf(stderr, "bench_renderers: %s\n", lm_last_error());
        return lm_exit_code(st);
    }
    return 0;
}
