/* tests/unit/test_mesh_io_isolate.c — readers run in a child process (common/mesh_io_isolate.c):
 * a model loaded there comes back whole (the textured spider through the GLB hand-over), a reader
 * that crashes or aborts becomes a one-line error while this process goes on, a reader's own
 * error comes back with its status and message, and FBX goes through it (assimp 5.2 aborts on
 * the kept fuzz input tests/fuzz/known/fbx_binary_tokenizer_abort). */
#include "test_support.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh_io.h"
#include "common/mesh_io_internal.h"

static lm_status load_spider(void *ctx, lm_mesh **out)
{
    return lm_mesh_load((const char *)ctx, NULL, out);
}

static lm_status crash(void *ctx, lm_mesh **out)
{
    (void)out;
    raise(*(const int *)ctx);
    return LM_OK;
}

static lm_status refuse(void *ctx, lm_mesh **out)
{
    (void)ctx;
    (void)out;
    return lm_fail(LM_E_RANGE, "model.fbx: 7 is out of range");
}

static void test_spider_comes_back_whole(void **state)
{
    (void)state;
    const char *path = lmt_spider_path();
    if (!path)
        skip();
    lm_mesh *here = NULL, *there = NULL;
    assert_int_equal(lm_mesh_load(path, NULL, &here), LM_OK);
    assert_int_equal(lm_io_load_isolated(load_spider, (void *)path, "spider", NULL, &there), LM_OK);
    assert_int_equal(there->live_tris, here->live_tris);
    assert_int_equal(there->live_verts, here->live_verts);
    assert_int_equal(there->n_materials, here->n_materials);
    assert_int_equal(there->attrs, here->attrs);
    for (uint32_t i = 0; i < here->n_materials; i++) {
        assert_non_null(there->materials[i].texture);
        assert_int_equal(there->materials[i].texture->width, here->materials[i].texture->width);
    }
    lm_mesh_destroy(here);
    lm_mesh_destroy(there);
}

static void test_crash_is_an_error(void **state)
{
    (void)state;
    const int sigs[] = {SIGSEGV, SIGABRT};
    for (int i = 0; i < 2; i++) {
        lm_mesh *m = NULL;
        lm_clear_error();
        assert_int_equal(lm_io_load_isolated(crash, (void *)&sigs[i], "bad.fbx", NULL, &m),
                         LM_E_FORMAT);
        assert_null(m);
        assert_non_null(strstr(lm_last_error(), "bad.fbx: the model reader crashed"));
        assert_null(strchr(lm_last_error(), '\n'));
    }
}

static void test_reader_error_comes_back(void **state)
{
    (void)state;
    lm_mesh *m = NULL;
    assert_int_equal(lm_io_load_isolated(refuse, NULL, "model.fbx", NULL, &m), LM_E_RANGE);
    assert_null(m);
    assert_string_equal(lm_last_error(), "model.fbx: 7 is out of range");
}

static void test_fbx_abort_input(void **state)
{
    (void)state;
    FILE *f = fopen(LUMESH_TEST_DATA "/../fuzz/known/fbx_binary_tokenizer_abort", "rb");
    assert_non_null(f);
    static uint8_t buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    lm_mesh *m = NULL;
    lm_status st = lm_mesh_load_memory(buf + 1, n - 1, "fbx", NULL, &m); /* byte 0: fuzz hint */
    assert_int_equal(st, LM_E_FORMAT);
    assert_null(m);
    assert_null(strchr(lm_last_error(), '\n'));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spider_comes_back_whole),
        cmocka_unit_test(test_crash_is_an_error),
        cmocka_unit_test(test_reader_error_comes_back),
        cmocka_unit_test(test_fbx_abort_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
