/* proto/wire_records.h — lumesh records to and from wire messages: triangle records, patches,
 * cameras. Decoding checks everything a peer could get wrong or make up: array lengths, finite
 * numbers, ids and material indices in range, counts within the limits below; a failure names the
 * first problem (LM_E_FORMAT or LM_E_RANGE) and the caller drops that peer.
 *
 * Encoding builds wire structures that point into the caller's records (no copies of the floats)
 * and into an lm_wire_arena for the pointer arrays; they are valid until the arena is reset.
 *
 * Patches against the current mesh: a patch's added record of an id the receiver holds (the
 * replica of the state both sides are at) leaves out every field of a corner — position, normal,
 * texture coordinates, colour — that is bit for bit the current record's (Tri.same), so a
 * triangle of which one corner's normal changed carries 3 floats, not 36. The receiver takes
 * those fields from its own current record; one it does not hold is a format error. */
#ifndef LM_PROTO_WIRE_RECORDS_H
#define LM_PROTO_WIRE_RECORDS_H

#include <stddef.h>
#include <stdint.h>

#include "common/patch.h"
#include "common/view.h"
#include "proto/wire.h"

#define LM_WIRE_MAX_PATCHES 65536u        /* patches in one Evaluate */
#define LM_WIRE_MAX_PATCH_TRIS (1u << 20) /* removed or added triangles in one patch */
#define LM_WIRE_FLOATS_PER_TRI 36u

/* Scratch memory for encoding: blocks kept across resets, freed by lm_wire_arena_free. */
typedef struct lm_wire_arena {
    uint8_t *block;
    size_t used, cap;
    void **old; /* blocks outgrown since the last reset */
    size_t n_old, cap_old;
} lm_wire_arena;

void lm_wire_arena_init(lm_wire_arena *a);
void lm_wire_arena_reset(lm_wire_arena *a);
void lm_wire_arena_free(lm_wire_arena *a);
/* n zeroed bytes (aligned to 16), or NULL when memory runs out. */
void *lm_wire_arena_alloc(lm_wire_arena *a, size_t n);

/* The current record of triangle `id` as the receiver holds it (NULL: none). */
typedef const lm_tri_data *(*lm_wire_current_fn)(const void *ctx, uint32_t id);

/* Tri.same: the fields left out of a record (those of the current record of its id), bit
 * 4 v + f for field f of corner v. */
enum { LM_WIRE_FIELD_POS, LM_WIRE_FIELD_NORMAL, LM_WIRE_FIELD_UV, LM_WIRE_FIELD_COLOR };
#define LM_WIRE_SAME_BIT(v, f) (1u << (4u * (unsigned)(v) + (unsigned)(f)))
#define LM_WIRE_SAME_ALL 0xFFFu

/* Encoding (pointers into the records; arrays from the arena). LM_E_NOMEM when it runs out. */
void lm_wire_tri_point(const lm_tri_data *t, Lumesh__Tri *out);
lm_status lm_wire_tris_encode(const lm_tri_data *tris, size_t n, lm_wire_arena *a,
                              Lumesh__Tri ***out);
lm_status lm_wire_patch_encode(const lm_patch *p, lm_wire_arena *a, Lumesh__Patch *out);
/* The same patch against the current records (current(ctx, id); current NULL: full records). */
lm_status lm_wire_patch_encode_against(const lm_patch *p, lm_wire_current_fn current,
                                       const void *ctx, lm_wire_arena *a, Lumesh__Patch *out);
lm_status lm_wire_view_encode(const lm_view *v, lm_wire_arena *a, Lumesh__View *out);

/* Decoding, checked. Materials must be below n_materials. */
lm_status lm_wire_tri_decode(const Lumesh__Tri *t, uint32_t n_materials, lm_tri_data *out);
/* Into p (emptied first; capacity kept). Full records only. */
lm_status lm_wire_patch_decode(const Lumesh__Patch *w, uint32_t n_materials, lm_patch *p);
/* A patch encoded against the current records current(ctx, id) (NULL: full records only). */
lm_status lm_wire_patch_decode_against(const Lumesh__Patch *w, uint32_t n_materials,
                                       lm_wire_current_fn current, const void *ctx, lm_patch *p);
/* A camera of width x height pixels. */
lm_status lm_wire_view_decode(const Lumesh__View *w, int width, int height, lm_view *out);

#endif
