/* common/image.h — 8-bit RGBA images in memory and their file I/O (through OpenImageIO, whose
 * C++ lives only in common/image_io_oiio.cpp behind this C header). Rows are stored top to bottom.
 */
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

/* Allocate a zeroed RGBA8 image. Sides must be 1..LM_IMAGE_MAX_SIDE. */
lm_status lm_image_create(int width, int height, lm_image **out);
void lm_image_destroy(lm_image *img);
lm_status lm_image_clone(const lm_image *src, lm_image **out);

/* Read any format OpenImageIO knows; converted to RGBA8 (grey/RGB expanded, alpha 255 if absent).
 */
lm_status lm_image_read(const char *path, lm_image **out);

/* Decode an image held in memory (e.g. a texture embedded in a glTF/GLB/FBX file). hint_ext
 * ("png", "jpg", ... or NULL) names the format; the bytes' signature wins when it is recognised. */
lm_status lm_image_read_memory(const void *data, size_t size, const char *hint_ext, lm_image **out);

/* Encode as PNG into a malloc'ed buffer (*out, *n bytes; the caller frees it with free()). */
lm_status lm_image_encode_png_memory(const lm_image *img, uint8_t **out, size_t *n);

/* Write PNG/JPEG/TGA/... chosen by extension; atomic (temp file + rename). */
lm_status lm_image_write(const char *path, const lm_image *img);

/* Write a single-channel 8-bit image (e.g. luminance or a difference map); atomic. */
lm_status lm_image_write_gray(const char *path, const uint8_t *gray, int width, int height);

#endif
