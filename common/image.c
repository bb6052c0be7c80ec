/* common/image.c — lm_image ownership: creation (zeroed RGBA8), destruction and deep copy.
 * File I/O lives in common/io/image_io_oiio.cpp. */
#include "common/image.h"

#include <stdlib.h>
#include <string.h>

lm_status lm_image_create(int width, int height, lm_image **out)
{
    if (width < 1 || height < 1 || width > LM_IMAGE_MAX_SIDE || height > LM_IMAGE_MAX_SIDE)
        return lm_fail(LM_E_RANGE, "image size %dx%d is outside 1..%d", width, height,
                       LM_IMAGE_MAX_SIDE);
    lm_image *img = calloc(1, sizeof *img);
    if (!img)
        return lm_fail(LM_E_NOMEM, "out of memory creating a %dx%d image", width, height);
    img->width = width;
    img->height = height;
    img->channels = 4;
    img->pixels = calloc((size_t)width * (size_t)height, 4);
    if (!img->pixels) {
        free(img);
        return lm_fail(LM_E_NOMEM, "out of memory creating a %dx%d image", width, height);
    }
    *out = img;
    return LM_OK;
}

void lm_image_destroy(lm_image *img)
{
    if (!img)
        return;
    free(img->pixels);
    free(img);
}

lm_status lm_image_clone(const lm_image *src, lm_image **out)
{
    LM_ASSERT(src != NULL && src->channels == 4);
    lm_image *img = NULL;
    lm_status s = lm_image_create(src->width, src->height, &img);
    if (s)
        return s;
    memcpy(img->pixels, src->pixels, (size_t)src->width * (size_t)src->height * 4);
    *out = img;
    return LM_OK;
}
