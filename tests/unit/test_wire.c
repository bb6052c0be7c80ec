/* tests/unit/test_wire.c — the wire protocol's guards: messages survive encoding, a frame that
 * unpacks into far more memory than it is long (empty sub-messages by the million) is refused by
 * the decoding budget, malformed frames and records are refused with one line, patches and cameras
 * come back bit for bit, and assets (mesh with a textured material) round-trip by content hash and
 * refuse truncation, bad counts, out-of-range indices and non-finite numbers; a targets asset
 * round-trips in place and refuses truncation, extra bytes, zero or oversized sizes and counts, and
 * leaves a set when dropped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh.h"
#include "common/patch.h"
#include "common/view.h"
#include "proto/asset.h"
#include "proto/wire.h"
#include "proto/wire_records.h"
#include "test_support.h"

static uint8_t *pack(lm_msg *m, size_t *n)
{
    *n = lumesh__msg__get_packed_size(m);
    uint8_t *buf = malloc(*n + 1);
    lumesh__msg__pack(m, buf);
    return buf;
}

static void test_roundtrip_patch(void **state)
{
    (void)state;
    lm_patch p, q;
    lm_patch_init(&p);
    lm_patch_init(&q);
    lm_tri_data t = {.id = 41, .material = 1};
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 3; i++)
            t.c[k].pos[i] = 0.1f * (float)(k + i);
    assert_int_equal(lm_patch_remove(&p, 40), LM_OK);
    assert_int_equal(lm_patch_add(&p, &t), LM_OK);
    lm_wire_arena a;
    lm_wire_arena_init(&a);
    Lumesh__Patch wp, *wpp = &wp;
    assert_int_equal(lm_wire_patch_encode(&p, &a, &wp), LM_OK);
    Lumesh__Evaluate e = LUMESH__EVALUATE__INIT;
    e.n_patches = 1, e.patches = &wpp;
    lm_msg m;
    lm_wire_msg_init(&m, 9, 4, LUMESH__MSG__BODY_EVALUATE, &e);
    size_t n;
    uint8_t *buf = pack(&m, &n);
    lm_wire_in in;
    assert_int_equal(lm_wire_decode(buf, n, &in), LM_OK);
    assert_true(in.msg->req == 9 && in.msg->seq == 4);
    assert_int_equal(in.msg->body_case, LUMESH__MSG__BODY_EVALUATE);
    assert_int_equal(lm_wire_patch_decode(in.msg->evaluate->patches[0], 2, &q), LM_OK);
    assert_int_equal(q.n_removed, 1);
    assert_int_equal(q.removed[0], 40);
    assert_memory_equal(&q.added[0], &t, sizeof t);
    /* the material must be in the worker's table */
    assert_int_equal(lm_wire_patch_decode(in.msg->evaluate->patches[0], 1, &q), LM_E_RANGE);
    assert_non_null(strstr(lm_last_error(), "material 1 of 1"));
    lm_wire_in_free(&in);
    free(buf);
    lm_wire_arena_free(&a);
    lm_patch_free(&p);
    lm_patch_free(&q);
}

/* Current records, as a receiver's replica holds them: ids 0..7. */
static lm_tri_data held[8];

static const lm_tri_data *held_current(const void *ctx, uint32_t id)
{
    (void)ctx;
    return id < 8 ? &held[id] : NULL;
}

static size_t packed_patch_bytes(const lm_patch *p, lm_wire_current_fn current)
{
    lm_wire_arena a;
    lm_wire_arena_init(&a);
    Lumesh__Patch wp;
    assert_int_equal(lm_wire_patch_encode_against(p, current, NULL, &a, &wp), LM_OK);
    size_t n = lumesh__patch__get_packed_size(&wp);
    lm_wire_arena_free(&a);
    return n;
}

/* A patch against the current records: what equals them is left out and comes back from the
 * receiver's own records, bit for bit; a receiver without the record refuses it. */
static void test_patch_against_current(void **state)
{
    (void)state;
    for (uint32_t id = 0; id < 8; id++) {
        held[id].id = id;
        held[id].material = id % 2;
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 12; i++)
                ((float *)&held[id].c[k])[i] = 0.37f * (float)(id * 40 + k * 12 + i) - 3.0f;
    }
    lm_patch p, q;
    lm_patch_init(&p);
    lm_patch_init(&q);
    lm_tri_data normals = held[2], moved = held[5], fresh = held[6];
    normals.c[1].normal[2] = -0.25f; /* a twin: only a normal changed */
    moved.c[0].pos[0] += 1.0f;       /* positions and normals change, uv and colour stay */
    moved.c[2].normal[1] = 0.125f;
    moved.material = 0;
    fresh.id = 30; /* not held: a full record */
    for (uint32_t id = 2; id <= 5; id += 3)
        assert_int_equal(lm_patch_remove(&p, id), LM_OK);
    assert_int_equal(lm_patch_add(&p, &normals), LM_OK);
    assert_int_equal(lm_patch_add(&p, &moved), LM_OK);
    assert_int_equal(lm_patch_add(&p, &fresh), LM_OK);
    lm_wire_arena a;
    lm_wire_arena_init(&a);
    Lumesh__Patch wp;
    assert_int_equal(lm_wire_patch_encode_against(&p, held_current, NULL, &a, &wp), LM_OK);
    assert_int_equal(wp.added[0]->same,
                     LM_WIRE_SAME_ALL & ~LM_WIRE_SAME_BIT(1, LM_WIRE_FIELD_NORMAL));
    assert_int_equal(wp.added[0]->n_corners, 3);
    assert_int_equal(wp.added[1]->same, LM_WIRE_SAME_ALL & ~LM_WIRE_SAME_BIT(0, LM_WIRE_FIELD_POS) &
                                            ~LM_WIRE_SAME_BIT(2, LM_WIRE_FIELD_NORMAL));
    assert_int_equal(wp.added[1]->n_corners, 6);
    assert_int_equal(wp.added[2]->same, 0);
    assert_int_equal(lm_wire_patch_decode_against(&wp, 2, held_current, NULL, &q), LM_OK);
    assert_int_equal(q.n_added, 3);
    assert_memory_equal(&q.added[0], &normals, sizeof normals);
    assert_memory_equal(&q.added[1], &moved, sizeof moved);
    assert_memory_equal(&q.added[2], &fresh, sizeof fresh);
    /* far fewer bytes than full records */
    assert_true(2 * packed_patch_bytes(&p, held_current) < packed_patch_bytes(&p, NULL) + 200);
    /* without current records, or where the receiver lacks the id, it is refused */
    assert_int_equal(lm_wire_patch_decode(&wp, 2, &q), LM_E_FORMAT);
    memmove(&held[2], &held[3], sizeof held[2]); /* id 2 no longer holds its record... */
    held[2].id = 2;
    assert_int_equal(lm_wire_patch_decode_against(&wp, 2, held_current, NULL, &q), LM_OK);
    assert_memory_not_equal(&q.added[0], &normals, sizeof normals); /* ...so it is another mesh */
    wp.added[0]->id = 9;
    assert_int_equal(lm_wire_patch_decode_against(&wp, 2, held_current, NULL, &q), LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "not in the mesh"));
    wp.added[0]->id = 2;
    wp.added[0]->n_corners = 2; /* the fields carried must match `same` */
    assert_int_equal(lm_wire_patch_decode_against(&wp, 2, held_current, NULL, &q), LM_E_FORMAT);
    wp.added[0]->n_corners = 3;
    wp.added[0]->same |= 1u << 12; /* no such field */
    assert_int_equal(lm_wire_patch_decode_against(&wp, 2, held_current, NULL, &q), LM_E_FORMAT);
    lm_wire_arena_free(&a);
    lm_patch_free(&p);
    lm_patch_free(&q);
}

static void test_bad_records(void **state)
{
    (void)state;
    float corners[36] = {0};
    Lumesh__Tri t = LUMESH__TRI__INIT;
    t.id = 1, t.n_corners = 35, t.corners = corners;
    lm_tri_data d;
    assert_int_equal(lm_wire_tri_decode(&t, 4, &d), LM_E_FORMAT);
    t.n_corners = 36;
    corners[7] = NAN;
    assert_int_equal(lm_wire_tri_decode(&t, 4, &d), LM_E_RANGE);
    corners[7] = 0;
    t.id = LM_MESH_MAX_TRIS;
    assert_int_equal(lm_wire_tri_decode(&t, 4, &d), LM_E_RANGE);
    t.id = 1;
    assert_int_equal(lm_wire_tri_decode(&t, 4, &d), LM_OK);
    Lumesh__View v = LUMESH__VIEW__INIT;
    float f[16] = {0};
    v.n_eye = 3, v.eye = f, v.n_dir = 3, v.dir = f, v.n_view = 16, v.view = f;
    v.n_proj = 16, v.proj = f, v.n_view_proj = 15, v.view_proj = f;
    lm_view out;
    assert_int_equal(lm_wire_view_decode(&v, 64, 64, &out), LM_E_FORMAT);
    v.n_view_proj = 16;
    assert_int_equal(lm_wire_view_decode(&v, 64, 8, &out), LM_E_RANGE);
    assert_int_equal(lm_wire_view_decode(&v, 64, 64, &out), LM_OK);
}

/* A patch of 3 million empty triangles: 2 bytes each on the wire, dozens unpacked. */
static void test_decode_budget(void **state)
{
    (void)state;
    size_t tris = 3000000, inner = 2 * tris;
    size_t n = 1 + 4 + inner + 1 + 4; /* Msg.evaluate(22) { Evaluate.patches(1) { added(2)... } } */
    uint8_t *buf = malloc(n + 16), *p = buf;
    *p++ = (22 << 3) | 2; /* Msg field 22, length-delimited */
    size_t patch_len = inner, eval_len = 1 + 4 + patch_len;
    for (int i = 0; i < 4; i++) /* varint of eval_len in 4 bytes */
        *p++ = (uint8_t)(((eval_len >> (7 * i)) & 0x7f) | (i < 3 ? 0x80 : 0));
    *p++ = (1 << 3) | 2; /* Evaluate.patches */
    for (int i = 0; i < 4; i++)
        *p++ = (uint8_t)(((patch_len >> (7 * i)) & 0x7f) | (i < 3 ? 0x80 : 0));
    for (size_t i = 0; i < tris; i++) {
        *p++ = (2 << 3) | 2; /* Patch.added, empty */
        *p++ = 0;
    }
    lm_wire_in in;
    lm_status st = lm_wire_decode(buf, (size_t)(p - buf), &in);
    assert_int_equal(st, LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "too large unpacked"));
    lm_wire_in_free(&in);
    /* garbage and empty frames */
    memset(buf, 0xff, 64);
    assert_int_equal(lm_wire_decode(buf, 64, &in), LM_E_FORMAT);
    lm_wire_in_free(&in);
    assert_int_equal(lm_wire_decode(buf, 0, &in), LM_E_FORMAT);
    lm_wire_in_free(&in);
    free(buf);
}

static lm_mesh *textured_grid(void)
{
    lm_mesh *m = lmt_make_grid(6);
    lm_image *tex;
    assert_int_equal(lm_image_create(8, 4, &tex), LM_OK);
    for (int i = 0; i < 8 * 4 * 4; i++)
        tex->pixels[i] = (uint8_t)(i * 7);
    float white[4] = {1, 1, 1, 1};
    assert_int_equal(lm_mesh_add_material(m, "tex", white, "t.png", tex, NULL), LM_OK);
    for (uint32_t t = 0; t < m->n_tris; t++)
        m->tris[t].material = t % 2 ? m->n_materials - 1 : 0;
    return m;
}

static void test_asset_roundtrip(void **state)
{
    (void)state;
    lm_mesh *m = textured_grid(), *back = NULL;
    lm_asset_set s;
    lm_asset_set_init(&s);
    lm_asset_hash h;
    assert_int_equal(lm_asset_pack_mesh(m, &s, &h), LM_OK);
    assert_int_equal(s.n, 2); /* the texture, then the mesh */
    const lm_asset *a = lm_asset_set_find(&s, &h);
    assert_non_null(a);
    lm_asset_hash *refs;
    uint32_t nr;
    assert_int_equal(lm_asset_refs(a->data, a->size, &refs, &nr), LM_OK);
    assert_int_equal(nr, 1);
    assert_non_null(lm_asset_set_find(&s, &refs[0]));
    free(refs);
    assert_int_equal(lm_asset_unpack_mesh(a->data, a->size, &s, &back), LM_OK);
    assert_true(lm_mesh_hash(back) == lm_mesh_hash(m));
    assert_int_equal(back->n_materials, m->n_materials);
    const lm_image *t0 = m->materials[m->n_materials - 1].texture;
    const lm_image *t1 = back->materials[back->n_materials - 1].texture;
    assert_memory_equal(t0->pixels, t1->pixels, 8 * 4 * 4);
    lm_mesh_destroy(back);
    /* the same content gives the same name: packing again adds nothing */
    lm_asset_hash h2;
    assert_int_equal(lm_asset_pack_mesh(m, &s, &h2), LM_OK);
    assert_memory_equal(h.b, h2.b, sizeof h.b);
    assert_int_equal(s.n, 2);
    lm_asset_set_free(&s);
    lm_mesh_destroy(m);
}

static void test_asset_refused(void **state)
{
    (void)state;
    lm_mesh *m = textured_grid(), *back = NULL;
    lm_asset_set s, empty;
    lm_asset_set_init(&s);
    lm_asset_set_init(&empty);
    lm_asset_hash h;
    assert_int_equal(lm_asset_pack_mesh(m, &s, &h), LM_OK);
    const lm_asset *a = lm_asset_set_find(&s, &h);
    uint8_t *copy = malloc(a->size);
    for (size_t cut = 0; cut < a->size; cut += a->size / 23 + 1) { /* truncated */
        assert_int_not_equal(lm_asset_unpack_mesh(a->data, cut, &s, &back), LM_OK);
        assert_null(back);
    }
    assert_int_equal(lm_asset_unpack_mesh(a->data, a->size, &empty, &back), LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "missing"));
    memcpy(copy, a->data, a->size);
    copy[12] = 0xff; /* a vertex count far beyond the bytes */
    assert_int_not_equal(lm_asset_unpack_mesh(copy, a->size, &s, &back), LM_OK);
    memcpy(copy, a->data, a->size);
    size_t tris = 8 + 16 + (size_t)36 * 12 + (size_t)36 * 40; /* first triangle's first wedge */
    copy[tris] = 0xfe;
    assert_int_equal(lm_asset_unpack_mesh(copy, a->size, &s, &back), LM_E_RANGE);
    memcpy(copy, a->data, a->size);
    uint32_t nan = 0x7fc00000u;
    memcpy(copy + 24, &nan, 4); /* the first vertex's x */
    assert_int_equal(lm_asset_unpack_mesh(copy, a->size, &s, &back), LM_E_RANGE);
    assert_null(back);
    free(copy);
    lm_asset_set_free(&s);
    lm_mesh_destroy(m);
}

static void put_le32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static void test_targets_asset(void **state)
{
    (void)state;
    uint8_t y[3 * 5 * 4];
    for (size_t i = 0; i < sizeof y; i++)
        y[i] = (uint8_t)(i * 7);
    lm_asset_set s;
    lm_asset_set_init(&s);
    lm_asset_hash h;
    assert_int_equal(lm_asset_pack_targets(5, 4, 3, y, &s, &h), LM_OK);
    const lm_asset *a = lm_asset_set_find(&s, &h);
    assert_non_null(a);
    assert_int_equal(a->size, 20 + sizeof y);
    lm_asset_targets t;
    assert_int_equal(lm_asset_unpack_targets(a->data, a->size, &t), LM_OK);
    assert_int_equal(t.width, 5);
    assert_int_equal(t.height, 4);
    assert_int_equal(t.n_views, 3);
    assert_memory_equal(t.luma, y, sizeof y);
    lm_asset_hash *refs = NULL;
    uint32_t n = 1;
    assert_int_equal(lm_asset_refs(a->data, a->size, &refs, &n), LM_OK);
    assert_int_equal(n, 0);
    free(refs);
    for (size_t cut = 0; cut < a->size; cut++) /* truncated */
        assert_int_not_equal(lm_asset_unpack_targets(a->data, cut, &t), LM_OK);
    uint8_t *copy = malloc(a->size + 1);
    memcpy(copy, a->data, a->size);
    copy[a->size] = 0;
    assert_int_equal(lm_asset_unpack_targets(copy, a->size + 1, &t), LM_E_FORMAT);
    const struct {
        size_t at;
        uint32_t v;
        lm_status want;
    } bad[] = {{8, 0, LM_E_RANGE},          {12, 0, LM_E_RANGE},   {16, 0, LM_E_RANGE},
               {8, 4097, LM_E_RANGE},       {16, 257, LM_E_RANGE}, {16, 4, LM_E_FORMAT},
               {8, 0xffffffffu, LM_E_RANGE}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        memcpy(copy, a->data, a->size);
        put_le32(copy + bad[i].at, bad[i].v);
        assert_int_equal(lm_asset_unpack_targets(copy, a->size, &t), bad[i].want);
        assert_null(strchr(lm_last_error(), '\n'));
    }
    memcpy(copy, a->data, a->size);
    copy[0] = 'X';
    assert_int_equal(lm_asset_unpack_targets(copy, a->size, &t), LM_E_FORMAT);
    assert_int_equal(lm_asset_pack_targets(0, 4, 3, y, &s, &h), LM_E_RANGE);
    assert_int_equal(lm_asset_pack_targets(5, 4, LM_MAX_VIEWS + 1, y, &s, &h), LM_E_RANGE);
    free(copy);
    lm_asset_hash h2; /* dropping one asset keeps the other */
    assert_int_equal(lm_asset_pack_targets(5, 4, 2, y, &s, &h2), LM_OK);
    assert_int_equal(s.n, 2);
    lm_asset_set_drop(&s, &h);
    assert_int_equal(s.n, 1);
    assert_null(lm_asset_set_find(&s, &h));
    assert_non_null(lm_asset_set_find(&s, &h2));
    lm_asset_set_drop(&s, &h); /* not there: nothing */
    assert_int_equal(s.n, 1);
    lm_asset_set_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_roundtrip_patch), cmocka_unit_test(test_bad_records),
        cmocka_unit_test(test_decode_budget),   cmocka_unit_test(test_asset_roundtrip),
        cmocka_unit_test(test_asset_refused),   cmocka_unit_test(test_patch_against_current),
        cmocka_unit_test(test_targets_asset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
