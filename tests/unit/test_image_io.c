/* tests/unit/test_image_io.c — the OpenImageIO shim: RGBA8 round trips (alpha kept as stored),
 * grey images, memory encode/decode, channel expansion, atomic writes and failures. */
#include "test_support.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "common/image.h"
#include "common/io/image_io.h"

static char *path_in(const char *dir, const char *name)
{
    static char buf[4][1024];
    static int next;
    char *b = buf[next++ % 4];
    snprintf(b, sizeof buf[0], "%s/%s", dir, name);
    return b;
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    closedir(d);
    return n;
}

/* 7x5 image, distinct pixels, alpha varying (0 included: premultiplication would lose colour). */
static lm_image *make_image(void)
{
    lm_image *img;
    assert_int_equal(lm_image_create(7, 5, &img), LM_OK);
    for (int i = 0; i < 35; i++) {
        uint8_t *p = img->pixels + 4 * i;
        p[0] = (uint8_t)(7 * i), p[1] = (uint8_t)(250 - 3 * i), p[2] = (uint8_t)(i * i % 256);
        p[3] = (uint8_t)(i % 3 == 0 ? 0 : i % 3 == 1 ? 77 : 255);
    }
    return img;
}

static void test_create_clone(void **state)
{
    (void)state;
    lm_image *img = make_image(), *copy = NULL;
    assert_int_equal(img->channels, 4);
    assert_int_equal(lm_image_clone(img, &copy), LM_OK);
    assert_memory_equal(img->pixels, copy->pixels, 7 * 5 * 4);
    lm_image *bad = NULL;
    assert_int_equal(lm_image_create(0, 5, &bad), LM_E_RANGE);
    assert_int_equal(lm_image_create(5, LM_IMAGE_MAX_SIDE + 1, &bad), LM_E_RANGE);
    assert_null(bad);
    lm_image_destroy(copy);
    lm_image_destroy(img);
    lm_image_destroy(NULL);
}

static void test_png_roundtrip(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    lm_image *img = make_image(), *back = NULL;
    const char *names[] = {"a.png", "a.tga", "a.tif"};
    for (int i = 0; i < 3; i++) {
        assert_int_equal(lm_image_write(path_in(dir, names[i]), img), LM_OK);
        assert_int_equal(lm_image_read(path_in(dir, names[i]), &back), LM_OK);
        assert_int_equal(back->width, 7);
        assert_int_equal(back->height, 5);
        assert_memory_equal(img->pixels, back->pixels, 7 * 5 * 4);
        lm_image_destroy(back);
    }
    assert_int_equal(count_entries(dir), 3); /* no temporary files left */
    lm_image_destroy(img);
    lmt_rmdir(dir);
}

/* The bytes decide which decoder reads a file, not its name: a TIFF named .png (read in a child
 * process) and a PNG named .tga (read here) both come back whole; bytes no decoder knows give one
 * line. */
static void test_bytes_decide(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    lm_image *img = make_image(), *back = NULL;
    const char *pairs[][2] = {{"t.tif", "tif_named.png"}, {"p.png", "png_named.tga"}};
    for (int i = 0; i < 2; i++) {
        assert_int_equal(lm_image_write(path_in(dir, pairs[i][0]), img), LM_OK);
        assert_int_equal(rename(path_in(dir, pairs[i][0]), path_in(dir, pairs[i][1])), 0);
        assert_int_equal(lm_image_read(path_in(dir, pairs[i][1]), &back), LM_OK);
        assert_memory_equal(img->pixels, back->pixels, 7 * 5 * 4);
        lm_image_destroy(back);
    }
    FILE *fp = fopen(path_in(dir, "noise.tga"), "wb");
    assert_non_null(fp);
    for (int i = 0; i < 300; i++)
        fputc((i * 37) & 255, fp);
    fclose(fp);
    back = NULL;
    assert_int_not_equal(lm_image_read(path_in(dir, "noise.tga"), &back), LM_OK);
    assert_null(back);
    assert_null(strchr(lm_last_error(), '\n'));
    lm_image_destroy(img);
    lmt_rmdir(dir);
}

static void test_jpeg_drops_alpha(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    lm_image *img, *back = NULL;
    assert_int_equal(lm_image_create(16, 16, &img), LM_OK);
    memset(img->pixels, 200, 16 * 16 * 4);
    assert_int_equal(lm_image_write(path_in(dir, "a.jpg"), img), LM_OK);
    assert_int_equal(lm_image_read(path_in(dir, "a.jpg"), &back), LM_OK);
    for (int i = 0; i < 16 * 16; i++) {
        assert_true(abs(back->pixels[4 * i] - 200) <= 2);
        assert_int_equal(back->pixels[4 * i + 3], 255);
    }
    lm_image_destroy(back);
    lm_image_destroy(img);
    lmt_rmdir(dir);
}

static void test_gray(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    uint8_t gray[6 * 4];
    for (int i = 0; i < 24; i++)
        gray[i] = (uint8_t)(i * 10);
    assert_int_equal(lm_image_write_gray(path_in(dir, "g.png"), gray, 6, 4), LM_OK);
    lm_image *back = NULL;
    assert_int_equal(lm_image_read(path_in(dir, "g.png"), &back), LM_OK);
    assert_int_equal(back->width, 6);
    for (int i = 0; i < 24; i++) { /* expanded: r = g = b = grey, opaque; rows top to bottom */
        const uint8_t *p = back->pixels + 4 * i;
        assert_int_equal(p[0], gray[i]);
        assert_int_equal(p[1], gray[i]);
        assert_int_equal(p[2], gray[i]);
        assert_int_equal(p[3], 255);
    }
    lm_image_destroy(back);
    lmt_rmdir(dir);
}

static void test_memory(void **state)
{
    (void)state;
    lm_image *img = make_image(), *back = NULL;
    uint8_t *png = NULL;
    size_t n = 0;
    assert_int_equal(lm_image_encode_png_memory(img, &png, &n), LM_OK);
    assert_true(n > 8);
    assert_memory_equal(png, "\x89PNG", 4);
    assert_int_equal(lm_image_read_memory(png, n, NULL, &back), LM_OK);
    assert_memory_equal(img->pixels, back->pixels, 7 * 5 * 4);
    lm_image_destroy(back);
    back = NULL; /* truncated and garbage bytes are refused */
    assert_int_not_equal(lm_image_read_memory(png, n / 2, "png", &back), LM_OK);
    assert_int_equal(lm_image_read_memory("garbage!", 8, "png", &back), LM_E_FORMAT);
    assert_int_equal(lm_image_read_memory(png, 0, "png", &back), LM_E_FORMAT);
    assert_null(back);
    free(png);
    lm_image_destroy(img);
}

static uint32_t crc32_of(const uint8_t *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
    }
    return ~c;
}

static size_t png_chunk(uint8_t *out, const char *type, const uint8_t *data, uint32_t len)
{
    out[0] = (uint8_t)(len >> 24), out[1] = (uint8_t)(len >> 16), out[2] = (uint8_t)(len >> 8);
    out[3] = (uint8_t)len;
    memcpy(out + 4, type, 4);
    if (len)
        memcpy(out + 8, data, len);
    uint32_t c = crc32_of(out + 4, len + 4);
    out[8 + len] = (uint8_t)(c >> 24), out[9 + len] = (uint8_t)(c >> 16);
    out[10 + len] = (uint8_t)(c >> 8), out[11 + len] = (uint8_t)c;
    return 12 + len;
}

/* A 200-byte PNG whose header claims 30000 x 30000 RGBA pixels (3.6 GB) is refused up front. */
static void test_png_bomb(void **state)
{
    (void)state;
    uint8_t png[256], ihdr[13] = {0, 0, 0x75, 0x30, 0, 0, 0x75, 0x30, 8, 6, 0, 0, 0};
    uint8_t idat[8] = {0x78, 0x9c, 0x63, 0, 0, 0, 0, 1};
    size_t n = 8;
    memcpy(png, "\x89PNG\r\n\x1a\n", 8);
    n += png_chunk(png + n, "IHDR", ihdr, sizeof ihdr);
    n += png_chunk(png + n, "IDAT", idat, sizeof idat);
    n += png_chunk(png + n, "IEND", NULL, 0);
    lm_image *img = NULL;
    assert_int_equal(lm_image_read_memory(png, n, "png", &img), LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "30000x30000"));
    assert_null(img);
}

static void test_failures(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    lm_image *img = make_image(), *back = NULL;
    assert_int_equal(lm_image_read(path_in(dir, "missing.png"), &back), LM_E_IO);
    assert_non_null(strstr(lm_last_error(), "missing.png"));
    assert_int_equal(lm_image_read(dir, &back), LM_E_IO);
    FILE *fp = fopen(path_in(dir, "junk.png"), "wb");
    fputs("this is not a png at all", fp);
    fclose(fp);
    assert_int_equal(lm_image_read(path_in(dir, "junk.png"), &back), LM_E_FORMAT);
    assert_null(back);
    assert_int_equal(lm_image_write("/proc/nope/x.png", img), LM_E_IO);
    assert_int_equal(lm_image_write(path_in(dir, "x.nosuchformat"), img), LM_E_UNSUPPORTED);
    assert_int_equal(mkdir(path_in(dir, "d.png"), 0755), 0);
    assert_int_equal(lm_image_write(path_in(dir, "d.png"), img), LM_E_IO);
    assert_int_equal(count_entries(dir), 2); /* junk.png and the directory: nothing half-written */
    lm_image_destroy(img);
    lmt_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_create_clone),     cmocka_unit_test(test_png_roundtrip),
        cmocka_unit_test(test_jpeg_drops_alpha), cmocka_unit_test(test_gray),
        cmocka_unit_test(test_memory),           cmocka_unit_test(test_png_bomb),
        cmocka_unit_test(test_failures),         cmocka_unit_test(test_bytes_decide),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
