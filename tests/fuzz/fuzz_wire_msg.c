/* tests/fuzz/fuzz_wire_msg.c — libFuzzer target for the wire protocol's decoding: any frame is
 * decoded with the bounded allocator (proto/wire.h) and, when it decodes, every record it carries
 * is checked the way the worker and the coordinator check them (proto/wire_records.h): triangles,
 * patches (full records, and against a replica holding the ids below 16), cameras, asset hashes
 * and chunks. Any input must give LM_OK or an error with a one-line
 * message; never a crash, a leak, a hang or an allocation beyond the budget.
 * Seeds: written by make_wire_seeds (scripts/test.sh). */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "common/log.h"
#include "proto/asset.h"
#include "proto/wire.h"
#include "proto/wire_records.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check(lm_status st)
{
    LM_ASSERT(st == LM_OK || (lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n')));
}

/* Current records of the ids below 16, as a worker's replica would hold them. */
static const lm_tri_data *current(const void *ctx, uint32_t id)
{
    static lm_tri_data held[16];
    (void)ctx;
    if (id >= 16)
        return NULL;
    held[id].id = id;
    return &held[id];
}

static void walk_patches(Lumesh__Patch **p, size_t n)
{
    lm_patch patch;
    lm_patch_init(&patch);
    for (size_t i = 0; i < n && i < 256; i++) {
        check(lm_wire_patch_decode(p[i], 8, &patch));
        check(lm_wire_patch_decode_against(p[i], 8, current, NULL, &patch));
    }
    lm_patch_free(&patch);
}

static void walk_tris(Lumesh__Tri **t, size_t n)
{
    for (size_t i = 0; i < n && i < 4096; i++) {
        lm_tri_data d;
        check(lm_wire_tri_decode(t[i], 8, &d));
    }
}

static void walk_job(const Lumesh__Job *j)
{
    for (size_t i = 0; i < j->n_views && i < LM_MAX_VIEWS; i++) {
        lm_view v;
        check(lm_wire_view_decode(j->views[i], (int)j->width, (int)j->height, &v));
    }
}

static void walk(const lm_msg *m)
{
    switch (m->body_case) {
    case LUMESH__MSG__BODY_EVALUATE:
        walk_patches(m->evaluate->patches, m->evaluate->n_patches);
        break;
    case LUMESH__MSG__BODY_COMMIT:
        if (m->commit->patch)
            walk_patches(&m->commit->patch, 1);
        break;
    case LUMESH__MSG__BODY_SET_MESH:
        walk_tris(m->set_mesh->tris, m->set_mesh->n_tris);
        break;
    case LUMESH__MSG__BODY_JOB:
        walk_job(m->job);
        break;
    default:
        (void)lm_wire_body_name(m);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lm_log_set_level(LM_LOG_ERROR);
    lm_wire_in in;
    lm_status st = lm_wire_decode(data, size, &in);
    check(st);
    if (st == LM_OK)
        walk(in.msg);
    lm_wire_in_free(&in);
    return 0;
}
