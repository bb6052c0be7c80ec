/* common/io/image_io_oiio.cpp — the only C++ in lumesh: the OpenImageIO 2.4 shim behind the C
 * header common/image.h. Decodes any format OpenImageIO knows (file or memory) into RGBA8, rows top
 * to bottom (lm_image_decode_*: in this process; common/io/image_read.c decides which bytes may
 * come here and which are decoded in a child process); writes by extension, atomically (temp file
 * beside the target, fsync, rename); encodes PNG into memory for GLB export. No C++ exception
 * crosses into C: every entry point catches them and converts them, like OpenImageIO's own errors,
 * into an lm_status with a one-line message. */
#define _Noreturn [[noreturn]]
extern "C" {
#include "common/image.h"
#include "common/io/atomic_file.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
}
#undef _Noreturn

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

namespace
{

/* First line of an OpenImageIO message, shortened, for a one-line lm_fail. */
std::string one_line(std::string msg)
{
    size_t nl = msg.find('\n');
    if (nl != std::string::npos)
        msg.resize(nl);
    if (msg.size() > 200)
        msg.resize(200);
    return msg.empty() ? std::string("unknown OpenImageIO error") : msg;
}

/* Expand nch (1..4) interleaved 8-bit channels to RGBA. */
void expand_rgba(const uint8_t *src, int nch, size_t npix, uint8_t *dst)
{
    for (size_t i = 0; i < npix; i++, src += nch, dst += 4) {
        switch (nch) {
        case 1:
            dst[0] = dst[1] = dst[2] = src[0];
            dst[3] = 255;
            break;
        case 2:
            dst[0] = dst[1] = dst[2] = src[0];
            dst[3] = src[1];
            break;
        case 3:
            dst[0] = src[0], dst[1] = src[1], dst[2] = src[2];
            dst[3] = 255;
            break;
        default:
            memcpy(dst, src, 4);
        }
    }
}

/* Read subimage 0 of an opened input into a new RGBA8 image. `encoded` is the size of the file
 * or buffer: a PNG cannot hold more than about 1032 bytes of pixels per byte (deflate's limit), so
 * a tiny PNG claiming a huge image is refused before gigabytes are allocated for it. */
lm_status read_opened(OIIO::ImageInput &in, const char *name, size_t encoded, lm_image **out)
{
    const OIIO::ImageSpec &spec = in.spec();
    if (spec.width < 1 || spec.height < 1 || spec.width > LM_IMAGE_MAX_SIDE ||
        spec.height > LM_IMAGE_MAX_SIDE || spec.depth > 1)
        return lm_fail(LM_E_RANGE, "image %s: size %dx%dx%d is outside 1..%d", name, spec.width,
                       spec.height, spec.depth, LM_IMAGE_MAX_SIDE);
    uint64_t raw = (uint64_t)spec.width * (uint64_t)spec.height * (uint64_t)spec.pixel_bytes();
    if (!strcmp(in.format_name(), "png") && raw > (uint64_t)encoded * 1100 + 65536)
        return lm_fail(LM_E_FORMAT, "image %s: %dx%d pixels cannot fit in %zu bytes of PNG", name,
                       spec.width, spec.height, encoded);
    /* JPEG: at best about 2 bits per 8x8 block of a component (a DC difference of 0, an end of
     * block), 256 pixels a byte; a 5 kB file claiming 30000x26000 pixels (found by fuzzing) would
     * have 2.4 GB allocated for it here and as much again in libjpeg. */
    uint64_t npix64 = (uint64_t)spec.width * (uint64_t)spec.height;
    if (!strcmp(in.format_name(), "jpeg") && npix64 > (uint64_t)encoded * 256 + ((uint64_t)1 << 22))
        return lm_fail(LM_E_FORMAT, "image %s: %dx%d pixels cannot fit in %zu bytes of JPEG", name,
                       spec.width, spec.height, encoded);
    if (spec.nchannels < 1)
        return lm_fail(LM_E_FORMAT, "image %s has no channels", name);
    int nch = spec.nchannels < 4 ? spec.nchannels : 4;
    size_t npix = (size_t)spec.width * (size_t)spec.height;
    std::vector<uint8_t> buf(npix * (size_t)nch);
    /* No worker threads: textures are small, and models may be read in a forked child
     * (mesh_io_isolate.c) where the parent's thread pool does not exist. */
    in.threads(1);
    if (!in.read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, buf.data()))
        return lm_fail(LM_E_FORMAT, "cannot decode image %s: %s", name,
                       one_line(in.geterror()).c_str());
    lm_image *img;
    lm_status s = lm_image_create(spec.width, spec.height, &img);
    if (s)
        return s;
    expand_rgba(buf.data(), nch, npix, img->pixels);
    *out = img;
    return LM_OK;
}

/* Configuration asking readers to keep alpha as stored (no premultiplication). */
OIIO::ImageSpec read_config()
{
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    return config;
}

lm_status read_file(const char *path, lm_image **out)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return lm_fail(LM_E_IO, "cannot read image %s: %s", path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return lm_fail(LM_E_IO, "cannot read image %s: not a regular file", path);
    OIIO::ImageSpec config = read_config();
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in)
        return lm_fail(LM_E_FORMAT, "cannot read image %s: %s", path,
                       one_line(OIIO::geterror()).c_str());
    return read_opened(*in, path, (size_t)st.st_size, out);
}

/* Format extension from the bytes' signature, or NULL when not recognised. */
const char *sniff_ext(const uint8_t *p, size_t n)
{
    if (n >= 8 && !memcmp(p, "\x89PNG\r\n\x1a\n", 8))
        return "png";
    if (n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF)
        return "jpg";
    if (n >= 2 && p[0] == 'B' && p[1] == 'M')
        return "bmp";
    if (n >= 4 && (!memcmp(p, "II*\0", 4) || !memcmp(p, "MM\0*", 4)))
        return "tif";
    if (n >= 6 && (!memcmp(p, "GIF87a", 6) || !memcmp(p, "GIF89a", 6)))
        return "gif";
    if (n >= 12 && !memcmp(p, "RIFF", 4) && !memcmp(p + 8, "WEBP", 4))
        return "webp";
    return NULL;
}

/* Whether a PNG stream holds whole chunks up to IEND. OpenImageIO 2.4's PNG reader leaks a string
 * each time libpng reads past the end of a truncated stream, so those are refused up front. */
bool png_complete(const uint8_t *p, size_t n)
{
    size_t at = 8;
    while (at + 12 <= n) {
        uint32_t len = (uint32_t)p[at] << 24 | (uint32_t)p[at + 1] << 16 |
                       (uint32_t)p[at + 2] << 8 | p[at + 3];
        if (len > n - at - 12)
            return false;
        if (!memcmp(p + at + 4, "IEND", 4))
            return true;
        at += 12 + (size_t)len;
    }
    return false;
}

lm_status read_memory(const void *data, size_t size, const char *hint_ext, lm_image **out)
{
    if (!data || size == 0)
        return lm_fail(LM_E_FORMAT, "embedded image is empty");
    const char *ext = sniff_ext((const uint8_t *)data, size);
    if (ext && !strcmp(ext, "png") && !png_complete((const uint8_t *)data, size))
        return lm_fail(LM_E_FORMAT, "embedded PNG image (%zu bytes) is truncated", size);
    if (!ext)
        ext = hint_ext && *hint_ext ? hint_ext : "png";
    std::string name = std::string("embedded.") + ext;
    OIIO::Filesystem::IOMemReader proxy(data, size);
    OIIO::ImageSpec config = read_config();
    /* OpenImageIO 2.4 ignores open()'s ioproxy argument when a config is given too: pass the
     * proxy inside the config instead. */
    void *proxy_ptr = &proxy;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
    auto in = OIIO::ImageInput::open(name, &config);
    if (!in)
        return lm_fail(LM_E_FORMAT, "cannot decode embedded %s image (%zu bytes): %s", ext, size,
                       one_line(OIIO::geterror()).c_str());
    return read_opened(*in, name.c_str(), size, out);
}

/* Aborts the temporary file unless committed (also when an exception unwinds). */
struct atomic_guard {
    lm_atomic_file f{};
    bool open = false;
    ~atomic_guard()
    {
        if (open)
            lm_atomic_abort(&f);
    }
};

/* Write w x h pixels of nch 8-bit channels to `path` (format by extension), atomically. */
lm_status write_pixels(const char *path, const uint8_t *px, int w, int h, int nch)
{
    if (!px || w < 1 || h < 1 || w > LM_IMAGE_MAX_SIDE || h > LM_IMAGE_MAX_SIDE)
        return lm_fail(LM_E_INVALID, "cannot write %s: bad image (%dx%d)", path, w, h);
    auto out = OIIO::ImageOutput::create(path);
    if (!out)
        return lm_fail(LM_E_UNSUPPORTED, "cannot write %s: no image format for this extension",
                       path);
    std::vector<uint8_t> rgb;
    if (nch == 4 && !out->supports("alpha")) { /* e.g. JPEG: drop alpha */
        rgb.resize((size_t)w * (size_t)h * 3);
        for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
            memcpy(&rgb[i * 3], px + i * 4, 3);
        px = rgb.data();
        nch = 3;
    }
    OIIO::ImageSpec spec(w, h, nch, OIIO::TypeDesc::UINT8);
    if (nch == 4)
        spec.attribute("oiio:UnassociatedAlpha", 1);
    atomic_guard g;
    lm_status s = lm_atomic_open(&g.f, path);
    if (s)
        return s;
    g.open = true;
    fclose((FILE *)g.f.fp); /* OpenImageIO writes the temporary file by name */
    g.f.fp = NULL;
    if (!out->open(g.f.tmp_path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px) ||
        !out->close())
        return lm_fail(LM_E_IO, "cannot write %s: %s", path, one_line(out->geterror()).c_str());
    g.open = false;
    return lm_atomic_commit(&g.f);
}

lm_status encode_png(const lm_image *img, uint8_t **out, size_t *n)
{
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto png = OIIO::ImageOutput::create("memory.png", &proxy);
    if (!png)
        return lm_fail(LM_E_INTERNAL, "OpenImageIO has no PNG writer: %s",
                       one_line(OIIO::geterror()).c_str());
    OIIO::ImageSpec spec(img->width, img->height, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!png->open("memory.png", spec) || !png->write_image(OIIO::TypeDesc::UINT8, img->pixels) ||
        !png->close())
        return lm_fail(LM_E_INTERNAL, "cannot encode a %dx%d PNG: %s", img->width, img->height,
                       one_line(png->geterror()).c_str());
    uint8_t *buf = (uint8_t *)malloc(bytes.size() ? bytes.size() : 1);
    if (!buf)
        return lm_fail(LM_E_NOMEM, "out of memory encoding a PNG");
    memcpy(buf, bytes.data(), bytes.size());
    *out = buf;
    *n = bytes.size();
    return LM_OK;
}

} // namespace

/* Run `body`, converting any C++ exception into an lm_status. */
template <typename F> static lm_status guarded(const char *what, F body)
{
    try {
        return body();
    } catch (const std::bad_alloc &) {
        return lm_fail(LM_E_NOMEM, "out of memory in %s", what);
    } catch (const std::exception &e) {
        return lm_fail(LM_E_INTERNAL, "%s: %s", what, one_line(e.what()).c_str());
    } catch (...) {
        return lm_fail(LM_E_INTERNAL, "%s: unknown C++ exception", what);
    }
}

extern "C" lm_status lm_image_decode_file(const char *path, lm_image **out)
{
    LM_ASSERT(path != NULL && out != NULL);
    return guarded("reading an image", [&] { return read_file(path, out); });
}

extern "C" lm_status lm_image_decode_memory(const void *data, size_t size, const char *hint_ext,
                                            lm_image **out)
{
    LM_ASSERT(out != NULL);
    return guarded("decoding an image", [&] { return read_memory(data, size, hint_ext, out); });
}

extern "C" lm_status lm_image_write(const char *path, const lm_image *img)
{
    LM_ASSERT(path != NULL && img != NULL && img->channels == 4);
    return guarded("writing an image",
                   [&] { return write_pixels(path, img->pixels, img->width, img->height, 4); });
}

extern "C" lm_status lm_image_write_gray(const char *path, const uint8_t *gray, int width,
                                         int height)
{
    LM_ASSERT(path != NULL);
    return guarded("writing an image", [&] { return write_pixels(path, gray, width, height, 1); });
}

extern "C" lm_status lm_image_encode_png_memory(const lm_image *img, uint8_t **out, size_t *n)
{
    LM_ASSERT(img != NULL && img->channels == 4 && out != NULL && n != NULL);
    return guarded("encoding a PNG", [&] { return encode_png(img, out, n); });
}
