/* tests/fuzz/fuzz_cameras.c — libFuzzer target for camera files (`--views-from`,
 * lm_cameras_parse): any input must give LM_OK with 1..LM_MAX_VIEWS cameras that
 * lm_camera_problem accepts and that make a view set, or an error status with a one-line message;
 * never a crash, a leak or a hang. Seeds: tests/fuzz/corpus/cameras/. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/camera_file.h"
#include "common/log.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static lm_camera cams[LM_MAX_VIEWS];
    static lm_view_set vs;
    lm_log_set_level(LM_LOG_ERROR);
    uint32_t n = 0;
    lm_status s = lm_cameras_parse((const char *)data, size, "fuzz", cams, &n);
    if (s != LM_OK) {
        LM_ASSERT(lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n'));
        return 0;
    }
    LM_ASSERT(n >= 1 && n <= LM_MAX_VIEWS);
    for (uint32_t i = 0; i < n; i++)
        LM_ASSERT(lm_camera_problem(&cams[i]) == NULL);
    const lm_view_spec spec = {.dist = LM_VIEW_DIST_CAMERAS, .count = n, .cameras = cams};
    const float centre[3] = {0, 0, 0};
    LM_ASSERT(lm_view_set_make_spec(&vs, &spec, LM_VIEWS_TRAINING, 16, centre, 1.0f) == LM_OK);
    return 0;
}
