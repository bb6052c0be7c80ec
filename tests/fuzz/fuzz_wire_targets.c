/* tests/fuzz/fuzz_wire_targets.c — libFuzzer target for a targets asset (proto/asset.h: the
 * target luminance images of a view set, which a worker takes instead of rendering them): any input
 * must give LM_OK with sizes and counts in their limits and exactly the bytes they need, or an
 * error with a one-line message; never a crash, a leak or a hang. A valid one packs back to the
 * same bytes. Seeds: tests/fuzz/corpus/wire_targets. */
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "common/view.h"
#include "proto/asset.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lm_log_set_level(LM_LOG_ERROR);
    lm_asset_targets t;
    lm_status st = lm_asset_unpack_targets(data, size, &t);
    LM_ASSERT(st == LM_OK || (lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n')));
    if (st != LM_OK)
        return 0;
    LM_ASSERT(t.width >= 1 && t.width <= LM_MAX_VIEW_SIZE && t.height >= 1 &&
              t.height <= LM_MAX_VIEW_SIZE && t.n_views >= 1 && t.n_views <= LM_MAX_VIEWS);
    LM_ASSERT(size == 20 + (size_t)t.n_views * t.width * t.height);
    lm_asset_set set;
    lm_asset_set_init(&set);
    lm_asset_hash h;
    LM_ASSERT(lm_asset_pack_targets(t.width, t.height, t.n_views, t.luma, &set, &h) == LM_OK);
    LM_ASSERT(set.n == 1 && set.items[0].size == size && !memcmp(set.items[0].data, data, size));
    lm_asset_set_free(&set);
    return 0;
}
