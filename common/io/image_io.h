/* common/io/image_io.h — images' file I/O, through OpenImageIO, whose C++ lives only in
 * common/io/image_io_oiio.cpp behind this C header. */
#ifndef LM_COMMON_IO_IMAGE_IO_H
#define LM_COMMON_IO_IMAGE_IO_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/image.h"

/* Read an image file; converted to RGBA8 (grey/RGB expanded, alpha 255 if absent). The bytes
 * decide the format, not the name: PNG and JPEG are decoded in this process (their readers are
 * fuzzed in the test gate, tests/fuzz/fuzz_image.c); any other format OpenImageIO knows is decoded
 * in a process of its own, so a decoder that crashes on a hostile file is a one-line LM_E_FORMAT
 * error and the caller is untouched (common/io/image_read.c). LM_E_IO: missing or not a regular
 * file. */
lm_status lm_image_read(const char *path, lm_image **out);

/* Decode an image held in memory (e.g. a texture embedded in a glTF/GLB/FBX file), under the same
 * rule as lm_image_read. hint_ext ("png", "jpg", ... or NULL) names the format; the bytes'
 * signature wins when it is recognised. */
lm_status lm_image_read_memory(const void *data, size_t size, const char *hint_ext, lm_image **out);

/* The OpenImageIO decoders themselves, in this process, for any format: only for bytes lumesh
 * wrote itself or that lm_image_read* vetted (common/io/image_io_oiio.cpp). */
lm_status lm_image_decode_file(const char *path, lm_image **out);
lm_status lm_image_decode_memory(const void *data, size_t size, const char *hint_ext,
                                 lm_image **out);

/* Encode as PNG into a malloc'ed buffer (*out, *n bytes; the caller frees it with free()). */
lm_status lm_image_encode_png_memory(const lm_image *img, uint8_t **out, size_t *n);

/* Write PNG/JPEG/TGA/... chosen by extension; atomic (temp file + rename). */
lm_status lm_image_write(const char *path, const lm_image *img);

/* Write a single-channel 8-bit image (e.g. luminance or a difference map); atomic. */
lm_status lm_image_write_gray(const char *path, const uint8_t *gray, int width, int height);

#endif
