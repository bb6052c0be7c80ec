/* coordinator/cli/cli_render.c — `lumesh render MODEL -o DIR [--views N] [--size S]
 * [--against ORIGINAL] [--device D]`: writes the colour images of MODEL's views as
 * DIR/view_00.png ...; with --against, the views are framed by ORIGINAL and DIR also receives the
 * original's images (target_XX.png) and the amplified absolute luminance differences
 * (diff_XX.png, 4 x |Ŷ - Y| clamped to 255). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/folders.h"
#include "common/image.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/quality/view_setup.h"
#include "coordinator/views/views.h"

#define CMD "render"
#define DIFF_GAIN 4

typedef struct render_args {
    const char *model, *dir, *against, *device;
    lm_view_spec views;
    uint32_t size;
} render_args;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: lumesh render MODEL -o DIR [--views N] [--size S] [--against ORIGINAL]\n"
            "                     [--device D]\n"
            "Writes the view images of MODEL as DIR/view_00.png, view_01.png, ...\n"
            "  -o, --output DIR      folder for the PNGs (created with its parents)\n"
            "  --views N             views (default %u), --size S  image side (default %d);\n"
            "                        --views upper[:N]: on the hemisphere above (+Y up)\n"
            "  --views-from FILE     the cameras of a JSON file instead (as lumesh optimize)\n"
            "  --against ORIGINAL    frame the views by ORIGINAL and also write its images\n"
            "                        (target_XX.png) and luminance differences (diff_XX.png)\n"
            "  --device D            auto (default), cpu, egl:N or host\n"
            "  -h, --help            this text\n",
            LM_DEFAULT_VIEWS, LM_DEFAULT_VIEW_SIZE);
}

static const co_cli_spec spec = {CMD, usage, 1, 1, "missing MODEL (see --help)", NULL, 1};

static int parse(int argc, char **argv, render_args *a)
{
    const co_opt opts[] = {CO_OPT_OUTPUT_NEEDED(&a->dir, "missing -o DIR (see --help)"),
                           CO_OPT_VIEWS(&a->views), CO_OPT_SIZE(&a->size),
                           CO_OPT_STR("against", 0, &a->against), CO_OPT_DEVICE(&a->device)};
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    a->model = argv[optind];
    return -1;
}

/* Write the colour image of a view (GL rows are bottom first; files top first). */
static lm_status write_colour(lm_views *v, uint32_t view, int size, const char *dir,
                              const char *prefix, uint8_t *rgba)
{
    lm_status st = v->ops->read_image(v, LM_IMAGE_RGBA, view, rgba);
    lm_image *img = NULL;
    if (st == LM_OK)
        st = lm_image_create(size, size, &img);
    if (st != LM_OK)
        return st;
    size_t row = (size_t)size * 4;
    for (int y = 0; y < size; y++)
        memcpy(img->pixels + row * y, rgba + row * (size - 1 - y), row);
    char path[4096];
    snprintf(path, sizeof path, "%s/%s_%02u.png", dir, prefix, view);
    st = lm_image_write(path, img);
    lm_image_destroy(img);
    return st;
}

static lm_status write_diff(lm_views *v, uint32_t view, int size, const char *dir, uint8_t *buf)
{
    size_t plane = (size_t)size * size;
    uint8_t *t = buf, *y = buf + plane, *d = buf + 2 * plane;
    lm_status st = v->ops->read_image(v, LM_IMAGE_TARGET_LUMA, view, t);
    if (st == LM_OK)
        st = v->ops->read_image(v, LM_IMAGE_CURRENT_LUMA, view, y);
    if (st != LM_OK)
        return st;
    for (int r = 0; r < size; r++)
        for (int x = 0; x < size; x++) {
            size_t src = (size_t)(size - 1 - r) * size + x;
            int diff = abs((int)t[src] - (int)y[src]) * DIFF_GAIN;
            d[(size_t)r * size + x] = (uint8_t)(diff > 255 ? 255 : diff);
        }
    char path[4096];
    snprintf(path, sizeof path, "%s/diff_%02u.png", dir, view);
    return lm_image_write_gray(path, d, size, size);
}

static lm_status set_model(lm_views *v, const lm_mesh *model)
{
    lm_status st = v->ops->set_materials(v, model->materials, model->n_materials);
    return st == LM_OK ? lm_views_set_mesh_from(v, model) : st;
}

/* The colour images of the last full render are read: right after creation the framing model's
 * (the original with --against, else the model itself), after set_mesh the model's. */
static lm_status render_all(const render_args *a, const lm_mesh *framing, const lm_mesh *model,
                            const lm_view_set *vs, uint8_t *buf)
{
    lm_views *v = NULL;
    co_views_desc d = {.original = framing, .views = vs, .device = a->device};
    lm_status st = co_views_create(&d, &v);
    for (uint32_t h = 0; st == LM_OK && a->against && h < vs->count; h++)
        st = write_colour(v, h, (int)a->size, a->dir, "target", buf);
    if (st == LM_OK && a->against)
        st = set_model(v, model);
    for (uint32_t h = 0; st == LM_OK && h < vs->count; h++)
        st = write_colour(v, h, (int)a->size, a->dir, "view", buf);
    for (uint32_t h = 0; st == LM_OK && a->against && h < vs->count; h++)
        st = write_diff(v, h, (int)a->size, a->dir, buf);
    lm_views_destroy(v);
    return st;
}

int co_cli_render(int argc, char **argv)
{
    render_args a = {
        .views = {.count = LM_DEFAULT_VIEWS}, .size = LM_DEFAULT_VIEW_SIZE, .device = "auto"};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    lm_mesh *model = NULL, *orig = NULL;
    lm_view_set *vs = NULL;
    uint8_t *buf = malloc((size_t)a.size * a.size * 4);
    lm_status st = buf ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for %u-pixel images", a.size);
    if (st == LM_OK)
        st = lm_mesh_load(a.model, NULL, &model);
    if (st == LM_OK && a.against)
        st = lm_mesh_load(a.against, NULL, &orig);
    if (st == LM_OK)
        st = co_view_set_of(orig ? orig : model, &a.views, (int)a.size, LM_VIEWS_TRAINING, &vs);
    if (st == LM_OK)
        st = lm_make_folders(a.dir);
    if (st == LM_OK)
        st = render_all(&a, orig ? orig : model, model, vs, buf);
    if (st == LM_OK)
        fprintf(stderr, "lumesh render: wrote %u view%s to %s\n", vs->count,
                vs->count == 1 ? "" : "s", a.dir);
    free(buf);
    free(vs);
    lm_mesh_destroy(model);
    lm_mesh_destroy(orig);
    return st ? co_cli_fail(CMD, st) : 0;
}
