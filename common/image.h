/* common/image.h — 8-bit RGBA images in memory. Rows are stored top to bottom. Reading and
 * writing them (OpenImageIO) is common/io/image_io.h. */
#ifndef LM_COMMON_IMAGE_H
#define LM_COMMON_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

#define LM_IMAGE_MAX_SIDE 32768

typedef struct lm_image {
    int width, height;
    int channels;    /* always 4 (RGBA8) for images made by this module */
    uint8_t *pixels; /* width*height*channels bytes, owned by the image */
} lm_image;

/* Luminance from RGBA8 with fixed integer NTSC weights: Y = (77 R + 150 G + 29 B + 128) >> 8. The
 * image energy is defined on it: the renderers and the report's pictures use this one. */
static inline uint8_t lm_luma(const uint8_t *rgba)
{
    return (uint8_t)((77u * rgba[0] + 150u * rgba[1] + 29u * rgba[2] + 128u) >> 8);
}

/* Allocate a zeroed RGBA8 image. Sides must be 1..LM_IMAGE_MAX_SIDE. */
lm_status lm_image_create(int width, int height, lm_image **out);
void lm_image_destroy(lm_image *img);
lm_status lm_image_clone(const lm_image *src, lm_image **out);

#endif
