/* tests/unit/test_camera_gltf.c — `--views-from` a glTF file (common/io/camera_gltf.h through
 * lm_cameras_parse / lm_cameras_read): a camera node's world transform (a parent's translation and
 * its own rotation) gives the camera's position, view direction, up and field of view; a .glb
 * gives the same cameras as its JSON, read from a file with a binary chunk after it;
 * orthographic cameras are left out; and each way a glTF can be wrong gives one line. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/camera_file.h"
#include "test_support.h"

/* A parent at (0, 0, 10) whose child turns 90 degrees about +Y and holds camera 1 (perspective,
 * yfov 0.5 rad); camera 0 is orthographic and its node is left out. */
static const char gltf[] =
    "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0, 2]}],"
    " \"nodes\": [{\"translation\": [0, 0, 10], \"children\": [1]},"
    "  {\"rotation\": [0, 0.70710678118654752, 0, 0.70710678118654752], \"camera\": 1},"
    "  {\"camera\": 0, \"translation\": [1, 2, 3]}],"
    " \"cameras\": [{\"type\": \"orthographic\", \"orthographic\": {\"xmag\": 1, \"ymag\": 1,"
    "  \"znear\": 0.1, \"zfar\": 10}},"
    "  {\"type\": \"perspective\", \"perspective\": {\"yfov\": 0.5, \"znear\": 0.1}}]}";

static void expect_near(const float *got, double x, double y, double z)
{
    assert_true(fabs(got[0] - x) < 1e-4 && fabs(got[1] - y) < 1e-4 && fabs(got[2] - z) < 1e-4);
}

static void check_cameras(const lm_camera *c, uint32_t n)
{
    assert_int_equal(n, 1);
    expect_near(c[0].position, 0, 0, 10);
    expect_near(c[0].target, -10, 0, 10); /* -Z turned about +Y: -X, one |position| away */
    expect_near(c[0].up, 0, 1, 0);
    assert_true(fabsf(c[0].fov_deg - (float)(0.5 * 180.0 / M_PI)) < 1e-4f);
}

static void test_gltf_transforms(void **state)
{
    (void)state;
    lm_camera c[LM_MAX_VIEWS];
    uint32_t n = 0;
    assert_int_equal(lm_cameras_parse(gltf, strlen(gltf), "t.gltf", c, &n), LM_OK);
    check_cameras(c, n);
}

/* A binary glTF of the JSON above (padded to 4 bytes), with a BIN chunk after it when `bin`. */
static char *make_glb(size_t *len, int bin)
{
    size_t json = (strlen(gltf) + 3) & ~(size_t)3, extra = bin ? 8 + 64 : 0;
    *len = 12 + 8 + json + extra;
    char *b = calloc(1, *len);
    assert_non_null(b);
    uint32_t head[5] = {0x46546C67u, 2, (uint32_t)*len, (uint32_t)json, 0x4E4F534Au};
    memcpy(b, head, sizeof head); /* little-endian machines only, as glTF itself */
    memset(b + 20, ' ', json);
    memcpy(b + 20, gltf, strlen(gltf));
    if (bin) {
        uint32_t chunk[2] = {64, 0x004E4942u};
        memcpy(b + 20 + json, chunk, sizeof chunk);
    }
    return b;
}

static void test_glb_file(void **state)
{
    (void)state;
    size_t len;
    char *glb = make_glb(&len, 1);
    lm_camera c[LM_MAX_VIEWS];
    uint32_t n = 0;
    assert_int_equal(lm_cameras_parse(glb, len, "t.glb", c, &n), LM_OK);
    check_cameras(c, n);
    char *dir = lmt_mkdtemp();
    char path[4096];
    snprintf(path, sizeof path, "%s/cams.glb", dir);
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(glb, 1, len, fp), len);
    fclose(fp);
    n = 0;
    assert_int_equal(lm_cameras_read(path, c, &n), LM_OK);
    check_cameras(c, n);
    remove(path);
    lmt_rmdir(dir);
    /* truncated anywhere in its header or JSON: refused, never read past the end */
    for (size_t cut = 0; cut < 20 + strlen(gltf); cut += 7) {
        n = 9;
        assert_int_not_equal(lm_cameras_parse(glb, cut, "t.glb", c, &n), LM_OK);
        assert_int_equal(n, 9);
    }
    free(glb);
}

static void expect_refused(const char *json, const char *why)
{
    lm_camera c[LM_MAX_VIEWS];
    uint32_t n = 7;
    lm_status st = lm_cameras_parse(json, strlen(json), "bad.gltf", c, &n);
    if (st != LM_E_FORMAT || !strstr(lm_last_error(), why) || !strstr(lm_last_error(), "bad.gltf"))
        fail_msg("%s: status %d, '%s', expected '%s'", json, st, lm_last_error(), why);
    assert_int_equal(n, 7);
}

#define ASSET "{\"asset\": {\"version\": \"2.0\"}, "
#define PERSP "\"cameras\": [{\"type\": \"perspective\", \"perspective\": {\"yfov\": 0.8}}]"

static void test_gltf_invalid(void **state)
{
    (void)state;
    expect_refused(ASSET "\"nodes\": [{\"mesh\": 0}]}", "no perspective camera");
    expect_refused(ASSET "\"nodes\": [{\"camera\": 0}], \"cameras\": [{\"type\": "
                         "\"orthographic\"}]}",
                   "orthographic ones are not supported");
    expect_refused(ASSET "\"nodes\": [{\"camera\": 3}], " PERSP "}", "names no camera");
    expect_refused(ASSET "\"nodes\": [{\"camera\": 0, \"rotation\": [0, 0, 0, 0]}], " PERSP "}",
                   "malformed node or transform");
    expect_refused(ASSET "\"nodes\": [{\"camera\": 0, \"matrix\": [1, 0, 0]}], " PERSP "}",
                   "malformed node or transform");
    expect_refused(ASSET "\"scenes\": [{\"nodes\": [0, 1]}], \"nodes\": [{\"children\": [1]},"
                         " {\"camera\": 0}], " PERSP "}",
                   "reached twice");
    expect_refused(ASSET "\"nodes\": [{\"children\": [5]}], " PERSP "}",
                   "a child is not a node index");
    expect_refused(ASSET "\"scene\": 2, \"scenes\": [{}], \"nodes\": [], " PERSP "}",
                   "names no scene");
    expect_refused(ASSET "\"nodes\": [{\"camera\": 0, \"scale\": [1, 1, 0]}], " PERSP "}",
                   "no view direction");
    expect_refused(ASSET "\"nodes\": [{\"camera\": 0}], \"cameras\": [{\"type\": \"perspective\","
                         " \"perspective\": {\"yfov\": 4}}]}",
                   "fov is outside");
}

/* A chain of nodes deeper than the reader walks: refused, not a stack overflow. */
static void test_gltf_deep(void **state)
{
    (void)state;
    enum { DEPTH = 2000 };
    size_t cap = DEPTH * 32 + 256;
    char *s = malloc(cap);
    assert_non_null(s);
    size_t k = (size_t)snprintf(s, cap, ASSET "\"nodes\": [");
    for (int i = 0; i < DEPTH; i++)
        k += (size_t)snprintf(s + k, cap - k, "%s{\"children\": [%d]}", i ? "," : "", i + 1);
    snprintf(s + k, cap - k, ",{\"camera\": 0}], " PERSP "}");
    expect_refused(s, "deeper than 1024");
    free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gltf_transforms),
        cmocka_unit_test(test_glb_file),
        cmocka_unit_test(test_gltf_invalid),
        cmocka_unit_test(test_gltf_deep),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
