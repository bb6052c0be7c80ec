/* tests/fuzz/fuzz_pm.c — libFuzzer target for progressive-mesh files (co_pm_read_memory, then
 * co_pm_extract at the coarsest, the finest and a middle count): any input must give LM_OK with
 * meshes that pass lm_mesh_validate, or an error status with a one-line message; never a crash,
 * a leak or a hang. Textures are decoded (their PNG headers are checked against the limits first).
 * Seeds: tests/fuzz/corpus/pm/ (an icosphere's 30 splits; a textured quad with none). */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "common/log.h"
#include "coordinator/simplify/pm.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void one_line_error(void)
{
    LM_ASSERT(lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n'));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lm_log_set_level(LM_LOG_ERROR);
    co_pm *pm = NULL;
    lm_status s = co_pm_read_memory(data, size, 1, &pm);
    if (s != LM_OK) {
        LM_ASSERT(pm == NULL);
        one_line_error();
        return 0;
    }
    uint32_t lo, hi;
    co_pm_range(pm, &lo, &hi);
    LM_ASSERT(lo <= hi);
    uint32_t counts[3] = {lo, lo + (hi - lo) / 2, hi};
    for (int i = 0; i < 3; i++) {
        lm_mesh *m = NULL;
        s = co_pm_extract(pm, counts[i], &m);
        if (s == LM_OK) {
            LM_ASSERT(m->live_verts == counts[i] && lm_mesh_validate(m) == LM_OK);
            lm_mesh_destroy(m);
        } else {
            LM_ASSERT(m == NULL && s == LM_E_FORMAT);
            one_line_error();
        }
    }
    co_pm_destroy(pm);
    return 0;
}
