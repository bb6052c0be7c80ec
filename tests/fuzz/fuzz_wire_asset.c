/* tests/fuzz/fuzz_wire_asset.c — libFuzzer target for the assets a job ships (proto/asset.h): the
 * first byte picks what the rest is read as (a mesh, a material table, or their texture
 * references), the second how many of the following bytes form a texture asset put into the set
 * first (so that references can resolve). Any input must give LM_OK with a valid mesh, or an
 * error with a one-line message; never a crash, a leak or a hang.
 * Seeds: written by make_wire_seeds (scripts/test.sh). */
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "proto/asset.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2)
        return 0;
    lm_log_set_level(LM_LOG_ERROR);
    int what = data[0] % 3;
    size_t tex = (size_t)data[1] * 16;
    data += 2, size -= 2;
    if (tex > size)
        tex = size;
    lm_asset_set set;
    lm_asset_set_init(&set);
    uint8_t *t = malloc(tex + 1);
    LM_ASSERT(t);
    memcpy(t, data, tex);
    LM_ASSERT(lm_asset_set_put(&set, t, tex, NULL) == LM_OK);
    data += tex, size -= tex;
    lm_mesh *m = NULL;
    lm_status st;
    if (what == 0) {
        st = lm_asset_unpack_mesh(data, size, &set, &m);
        LM_ASSERT(st != LM_OK || lm_mesh_validate(m) == LM_OK);
    } else if (what == 1) {
        st = lm_asset_unpack_materials(data, size, &set, &m);
    } else {
        lm_asset_hash *refs = NULL;
        uint32_t n = 0;
        st = lm_asset_refs(data, size, &refs, &n);
        free(refs);
    }
    LM_ASSERT(st == LM_OK || (lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n')));
    lm_mesh_destroy(m);
    lm_asset_set_free(&set);
    return 0;
}
