/* tests/fuzz/fuzz_image.c — libFuzzer target for the textures lumesh decodes in its own process
 * (lm_image_read_memory; common/io/image_read.c): PNG and JPEG, by their signatures, through
 * OpenImageIO and libpng / libjpeg. Every other format goes to a decoder process of its own
 * there, where a crash is an error status; inputs without a PNG or JPEG signature are skipped
 * here (each would start that process: ten runs a second instead of thousands), and the hand-back
 * is tested by test_image_io. The first byte picks the format hint, the rest is the image. Any
 * input must give LM_OK with an image inside the limits, or an error status with a one-line
 * message; never a crash, a leak or a hang. Seeds: tests/fuzz/corpus/image/ (small PNG and JPEG
 * files: grey, RGB, RGBA, palette, 16-bit, interlaced, progressive). */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "common/image.h"
#include "common/io/image_io.h"
#include "common/log.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const hints[] = {"png", "jpg", "tga", NULL};
    if (size < 1)
        return 0;
    const uint8_t *p = data + 1;
    size_t n = size - 1;
    int png = n >= 8 && !memcmp(p, "\x89PNG\r\n\x1a\n", 8);
    int jpeg = n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF;
    if (!png && !jpeg)
        return 0;
    lm_log_set_level(LM_LOG_ERROR);
    lm_image *img = NULL;
    lm_status s = lm_image_read_memory(data + 1, size - 1, hints[data[0] % 4], &img);
    if (s == LM_OK) {
        LM_ASSERT(img != NULL && img->channels == 4 && img->width >= 1 && img->height >= 1 &&
                  img->width <= LM_IMAGE_MAX_SIDE && img->height <= LM_IMAGE_MAX_SIDE);
        lm_image_destroy(img);
    } else {
        LM_ASSERT(img == NULL && lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n'));
    }
    return 0;
}
