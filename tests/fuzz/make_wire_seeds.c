/* tests/fuzz/make_wire_seeds.c — writes seed inputs for fuzz_wire_msg and fuzz_wire_asset into
 * two folders: one valid frame of every message kind the protocol has, and valid mesh, material
 * and texture assets (with the two prefix bytes fuzz_wire_asset reads); and for fuzz_stream, into
 * a third, every message as two frames of a local worker's link. Made from the schema as it is, so
 * the seeds never fall behind it.  usage: make_wire_seeds MSG_DIR ASSET_DIR [STREAM_DIR] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh.h"
#include "common/patch.h"
#include "common/view.h"
#include "proto/asset.h"
#include "proto/wire.h"
#include "proto/wire_records.h"

static void write_file(const char *dir, const char *name, const void *data, size_t n)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, n, f) != n) {
        fprintf(stderr, "make_wire_seeds: cannot write %s\n", path);
        exit(1);
    }
    fclose(f);
}

static const char *stream_dir; /* also each message as two frames of a local link */

/* The message as it crosses a local worker's link (proto/stream.h), twice in a row. */
static void write_stream(const char *name, const uint8_t *msg, size_t n)
{
    uint8_t *buf = malloc(2 * (n + 4));
    for (int k = 0; k < 2; k++) {
        uint8_t *h = buf + (size_t)k * (n + 4);
        for (int i = 0; i < 4; i++)
            h[i] = (uint8_t)(n >> (8 * i));
        memcpy(h + 4, msg, n);
    }
    write_file(stream_dir, name, buf, 2 * (n + 4));
    free(buf);
}

static void write_msg(const char *dir, const char *name, Lumesh__Msg__BodyCase c, void *body)
{
    lm_msg m;
    lm_wire_msg_init(&m, 7, 3, c, body);
    size_t n = lumesh__msg__get_packed_size(&m);
    uint8_t *buf = malloc(n + 1);
    lumesh__msg__pack(&m, buf);
    write_file(dir, name, buf, n);
    if (stream_dir)
        write_stream(name, buf, n);
    free(buf);
}

static void make_tris(lm_tri_data *t, int n)
{
    memset(t, 0, (size_t)n * sizeof *t);
    for (int i = 0; i < n; i++) {
        t[i].id = (uint32_t)i;
        for (int k = 0; k < 3; k++) {
            t[i].c[k].pos[0] = (float)(i + k);
            t[i].c[k].pos[1] = (float)k;
            t[i].c[k].normal[2] = 1.0f;
            t[i].c[k].color[0] = t[i].c[k].color[1] = t[i].c[k].color[2] = t[i].c[k].color[3] = 1;
        }
    }
}

/* The current record of id among the ten seed triangles. */
static const lm_tri_data *current_of(const void *ctx, uint32_t id)
{
    return id < 10 ? &((const lm_tri_data *)ctx)[id] : NULL;
}

static void msg_seeds(const char *dir)
{
    lm_wire_arena a;
    lm_wire_arena_init(&a);
    lm_tri_data tris[10];
    make_tris(tris, 10);
    Lumesh__Hello h = LUMESH__HELLO__INIT;
    h.version = LM_WIRE_VERSION, h.host = "host", h.device = "host", h.renderer = "llvmpipe";
    h.renderer_id = "0123456789abcdef";
    write_msg(dir, "hello", LUMESH__MSG__BODY_HELLO, &h);
    lm_view_set vs;
    float c[3] = {0, 0, 0};
    lm_view_set_make(&vs, 3, 64, c, 1.0f);
    Lumesh__View v[3], *vp[3];
    for (int i = 0; i < 3; i++) {
        lm_wire_view_encode(&vs.views[i], &a, &v[i]);
        vp[i] = &v[i];
    }
    uint8_t hash[LM_ASSET_HASH_BYTES] = {1, 2, 3};
    Lumesh__Job j = LUMESH__JOB__INIT;
    j.job = 1, j.original = (ProtobufCBinaryData){sizeof hash, hash}, j.width = j.height = 64;
    j.n_views = 3, j.views = vp;
    write_msg(dir, "job", LUMESH__MSG__BODY_JOB, &j);
    Lumesh__SetMesh sm = LUMESH__SET_MESH__INIT;
    sm.n_tris = 10;
    lm_wire_tris_encode(tris, 10, &a, &sm.tris);
    write_msg(dir, "set_mesh", LUMESH__MSG__BODY_SET_MESH, &sm);
    lm_patch p;
    lm_patch_init(&p);
    lm_patch_remove(&p, 3);
    lm_patch_add(&p, &tris[3]);
    Lumesh__Patch wp[3], *wpp[3];
    for (int i = 0; i < 3; i++) {
        lm_wire_patch_encode(&p, &a, &wp[i]);
        wpp[i] = &wp[i];
    }
    Lumesh__Evaluate e = LUMESH__EVALUATE__INIT;
    e.n_patches = 3, e.patches = wpp;
    write_msg(dir, "evaluate", LUMESH__MSG__BODY_EVALUATE, &e);
    Lumesh__Commit cm = LUMESH__COMMIT__INIT;
    cm.patch = &wp[0];
    write_msg(dir, "commit", LUMESH__MSG__BODY_COMMIT, &cm);
    /* against the current records (Tri.same): triangle 3 with new normals only */
    lm_tri_data moved = tris[3];
    moved.c[1].normal[0] = 0.5f;
    lm_patch_reset(&p);
    lm_patch_remove(&p, 3);
    lm_patch_add(&p, &moved);
    Lumesh__Patch ws, *wsp = &ws;
    lm_wire_patch_encode_against(&p, current_of, tris, &a, &ws);
    e.n_patches = 1, e.patches = &wsp;
    write_msg(dir, "evaluate_same", LUMESH__MSG__BODY_EVALUATE, &e);
    Lumesh__SetSurface ss = LUMESH__SET_SURFACE__INIT;
    ss.k = 12.5, ss.views_first = 0;
    write_msg(dir, "set_surface", LUMESH__MSG__BODY_SET_SURFACE, &ss);
    ProtobufCBinaryData hs[2] = {{sizeof hash, hash}, {sizeof hash, hash}};
    Lumesh__Offer o = LUMESH__OFFER__INIT;
    o.n_assets = 2, o.assets = hs;
    write_msg(dir, "offer", LUMESH__MSG__BODY_OFFER, &o);
    Lumesh__Asset as = LUMESH__ASSET__INIT;
    as.hash = hs[0], as.size = 16, as.offset = 0, as.data = (ProtobufCBinaryData){16, hash};
    write_msg(dir, "asset", LUMESH__MSG__BODY_ASSET, &as);
    int64_t d[3] = {-5, 0, 12};
    Lumesh__Deltas de = LUMESH__DELTAS__INIT;
    de.n_delta = 3, de.delta = d;
    write_msg(dir, "deltas", LUMESH__MSG__BODY_DELTAS, &de);
    float pts[6] = {0, 0, 0, 1, 1, 1};
    Lumesh__Potentials po = LUMESH__POTENTIALS__INIT;
    po.n_points = 6, po.points = pts;
    write_msg(dir, "potentials", LUMESH__MSG__BODY_POTENTIALS, &po);
    Lumesh__Failure f = LUMESH__FAILURE__INIT;
    f.code = 1, f.message = "no";
    write_msg(dir, "failure", LUMESH__MSG__BODY_FAILURE, &f);
    Lumesh__Assign as2 = LUMESH__ASSIGN__INIT;
    as2.job = 1, as2.first = 0, as2.count = 3;
    write_msg(dir, "assign", LUMESH__MSG__BODY_ASSIGN, &as2);
    uint8_t lane_bytes[24] = {0x4c, 0x4e, 0x52, 0x51, 1, 0, 0, 0}; /* not a whole request */
    Lumesh__RunLane rl = LUMESH__RUN_LANE__INIT;
    rl.job = 1, rl.group = 2, rl.lane = 1, rl.start_hash = 42, rl.surface = 1;
    rl.request = (ProtobufCBinaryData){sizeof lane_bytes, lane_bytes};
    rl.start = (ProtobufCBinaryData){16, hash};
    rl.config = (ProtobufCBinaryData){8, hash};
    write_msg(dir, "run_lane", LUMESH__MSG__BODY_RUN_LANE, &rl);
    rl.start = (ProtobufCBinaryData){0, NULL}; /* the next group's start as a delta */
    rl.group = 3, rl.base_group = 2;
    rl.start_delta = (ProtobufCBinaryData){16, hash};
    write_msg(dir, "run_lane_delta", LUMESH__MSG__BODY_RUN_LANE, &rl);
    rl.queue_delta = (ProtobufCBinaryData){16, hash}; /* and its collapse queue */
    write_msg(dir, "run_lane_queue_delta", LUMESH__MSG__BODY_RUN_LANE, &rl);
    rl.start_delta = rl.queue_delta = (ProtobufCBinaryData){0, NULL};
    rl.start = (ProtobufCBinaryData){16, hash}, rl.queue = (ProtobufCBinaryData){8, hash};
    write_msg(dir, "run_lane_queue", LUMESH__MSG__BODY_RUN_LANE, &rl);
    Lumesh__LaneDone ld = LUMESH__LANE_DONE__INIT;
    ld.group = 2, ld.lane = 1, ld.busy_us = 1500;
    ld.result = (ProtobufCBinaryData){sizeof lane_bytes, lane_bytes};
    write_msg(dir, "lane_done", LUMESH__MSG__BODY_LANE_DONE, &ld);
    lm_patch_free(&p);
    lm_wire_arena_free(&a);
}

/* An octahedron with a textured material. */
static lm_mesh *small_mesh(void)
{
    lm_mesh *m;
    lm_mesh_create(&m);
    lm_image *tex;
    lm_image_create(2, 2, &tex);
    memset(tex->pixels, 200, 16);
    float white[4] = {1, 1, 1, 1};
    lm_mesh_add_material(m, "skin", white, NULL, tex, NULL);
    const float p[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 6; i++) {
        uint32_t v;
        lm_mesh_add_vertex(m, p[i], &v);
        lm_wedge w = {.vertex = v, .normal = {p[i][0], p[i][1], p[i][2]}, .color = {1, 1, 1, 1}};
        lm_mesh_add_wedge(m, &w, NULL);
    }
    const uint32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int i = 0; i < 8; i++)
        lm_mesh_add_tri(m, f[i], 0, NULL);
    return m;
}

/* prefix (kind, texture bytes / 16), the texture asset, the asset. */
static void write_asset(const char *dir, const char *name, int kind, const lm_asset *tex,
                        const lm_asset *a)
{
    size_t n = 2 + tex->size + a->size;
    uint8_t *buf = malloc(n);
    buf[0] = (uint8_t)kind;
    buf[1] = (uint8_t)(tex->size / 16);
    memcpy(buf + 2, tex->data, tex->size);
    memcpy(buf + 2 + tex->size, a->data, a->size);
    write_file(dir, name, buf, n);
    free(buf);
}

static void asset_seeds(const char *dir)
{
    lm_mesh *m = small_mesh();
    lm_asset_set s;
    lm_asset_set_init(&s);
    lm_asset_hash mh, th;
    lm_asset_pack_mesh(m, &s, &mh);
    lm_asset_pack_materials(m->materials, m->n_materials, &s, &th);
    const lm_asset *mesh = lm_asset_set_find(&s, &mh), *mats = lm_asset_set_find(&s, &th);
    const lm_asset *tex = NULL;
    for (uint32_t i = 0; i < s.n; i++)
        if (&s.items[i] != mesh && &s.items[i] != mats)
            tex = &s.items[i];
    write_asset(dir, "mesh", 0, tex, mesh);
    write_asset(dir, "materials", 1, tex, mats);
    write_asset(dir, "refs", 2, tex, mesh);
    lm_asset_set_free(&s);
    lm_mesh_destroy(m);
}

int main(int argc, char **argv)
{
    if (argc != 3 && argc != 4) {
        fprintf(stderr, "usage: make_wire_seeds MSG_DIR ASSET_DIR [STREAM_DIR]\n");
        return 1;
    }
    stream_dir = argc == 4 ? argv[3] : NULL;
    msg_seeds(argv[1]);
    asset_seeds(argv[2]);
    return 0;
}
