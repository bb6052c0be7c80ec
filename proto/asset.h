/* proto/asset.h — what a job ships to its workers, content-addressed: a mesh (the original: alive
 * geometry and its material table), a material table alone (the current mesh's), and textures
 * (decoded RGBA8 pixels, so every worker samples the same texels whatever its image libraries).
 * Each asset is a byte string named by its 32-byte BLAKE2b hash; meshes and material tables name
 * their textures by hash, so a texture crosses the wire once per worker however often it is used.
 *
 * Formats (little-endian, floats as IEEE-754 bits):
 *   texture   "LMTEX1\0\0" u32 width, u32 height, width*height*4 bytes (rows top first)
 *   materials "LMMAT1\0\0" u32 n, n x {char name[64], f32 diffuse[4], u8 has_texture,
 *             hash[32] texture}, then only where some materials have normal maps: u32 k,
 *             k x {u32 material (ascending), hash[32] normal map} (a table without normal maps
 *             keeps the bytes it had before them; older workers refuse one with them)
 *   mesh      "LMMSH1\0\0" u32 attrs, u32 n_verts, n_wedges, n_tris, then positions (3 f32),
 *             wedges (u32 vertex, f32 normal[3], uv[2], colour[4]), triangles (u32 w[3],
 *             u32 material), then a material table as above (without its magic)
 *   targets   "LMTGT1\0\0" u32 width, u32 height, u32 n_views, then n_views images of width*height
 *             8-bit luminance bytes (the target Ŷ of each view of a job's view set, in its order,
 *             rows bottom first as worker/render/shared/image_store.h keeps them)
 * Decoding checks every count against the bytes present and the lumesh limits, every index, and
 * every number (finite), before anything is built: a malformed asset is LM_E_FORMAT/LM_E_RANGE
 * with a one-line message, never a crash. */
#ifndef LM_PROTO_ASSET_H
#define LM_PROTO_ASSET_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/mesh.h"

#define LM_ASSET_HASH_BYTES 32
#define LM_ASSET_MAX_BYTES ((size_t)1 << 34) /* 16 GiB: any asset larger is refused */

typedef struct lm_asset_hash {
    uint8_t b[LM_ASSET_HASH_BYTES];
} lm_asset_hash;

typedef struct lm_asset {
    lm_asset_hash hash;
    uint8_t *data; /* owned */
    size_t size;
} lm_asset;

/* A set of assets by hash (no duplicates). */
typedef struct lm_asset_set {
    lm_asset *items;
    uint32_t n, cap;
} lm_asset_set;

void lm_asset_hash_of(const void *data, size_t n, lm_asset_hash *out);
/* "ab12…" (first 8 bytes in hex) for messages; buf of at least 17 bytes. */
const char *lm_asset_hash_short(const lm_asset_hash *h, char *buf);

void lm_asset_set_init(lm_asset_set *s);
void lm_asset_set_free(lm_asset_set *s);
const lm_asset *lm_asset_set_find(const lm_asset_set *s, const lm_asset_hash *h);
/* Frees and removes the asset named h, if there (the others keep their order). */
void lm_asset_set_drop(lm_asset_set *s, const lm_asset_hash *h);
/* dst (empty, initialised) gets a copy of every asset of src, hashes as they are (none computed
 * again). On failure dst is left empty. */
lm_status lm_asset_set_copy(lm_asset_set *dst, const lm_asset_set *src);
/* Takes ownership of data (freed here on failure, or when already present). */
lm_status lm_asset_set_put(lm_asset_set *s, uint8_t *data, size_t size, lm_asset_hash *out);

/* Packing: the asset and every texture it refers to go into s; *out names the asset. */
lm_status lm_asset_pack_mesh(const lm_mesh *m, lm_asset_set *s, lm_asset_hash *out);
lm_status lm_asset_pack_materials(const lm_material *mats, uint32_t n, lm_asset_set *s,
                                  lm_asset_hash *out);

/* The textures an asset refers to (none for a texture): *refs malloc'ed (free it), *n. */
lm_status lm_asset_refs(const uint8_t *data, size_t size, lm_asset_hash **refs, uint32_t *n);

/* Unpacking; the textures are looked up in s (LM_E_FORMAT naming the hash when one is missing).
 * A materials asset comes back as a mesh without geometry holding the material table. */
lm_status lm_asset_unpack_mesh(const uint8_t *data, size_t size, const lm_asset_set *s,
                               lm_mesh **out);
lm_status lm_asset_unpack_materials(const uint8_t *data, size_t size, const lm_asset_set *s,
                                    lm_mesh **out);

/* A targets asset read in place: luma points into the asset's bytes (n_views * width * height of
 * them, view after view), valid while they are. */
typedef struct lm_asset_targets {
    uint32_t width, height, n_views;
    const uint8_t *luma;
} lm_asset_targets;

/* Pack the n_views targets of width x height (luma: view after view) into s; *out names them. */
lm_status lm_asset_pack_targets(uint32_t width, uint32_t height, uint32_t n_views,
                                const uint8_t *luma, lm_asset_set *s, lm_asset_hash *out);
/* Read a targets asset: the magic, the size in 1..LM_MAX_VIEW_SIZE, the count in 1..LM_MAX_VIEWS
 * and the byte count exactly, else LM_E_FORMAT/LM_E_RANGE with a one-line message. */
lm_status lm_asset_unpack_targets(const uint8_t *data, size_t size, lm_asset_targets *out);

#endif
