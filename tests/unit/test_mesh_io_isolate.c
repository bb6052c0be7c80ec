/* tests/unit/test_mesh_io_isolate.c — models read in a process of their own
 * (common/io/mesh_io_isolate.c): a model read there comes back whole (the textured spider, its
 * textures found in its own folder, through the GLB hand-back), the reader's own errors come back
 * with their status and message (the options reach it), and files that crash assimp 5.2 (a GLB
 * that reads through null, an FBX that aborts) are one-line errors while this process goes on. */
#include "test_support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/io/mesh_io.h"
#include "common/io/mesh_io_internal.h"

static uint8_t *read_whole(const char *path, size_t *n)
{
    uint8_t *data = NULL;
    assert_int_equal(lm_io_read_file(path, &data, n), LM_OK);
    return data;
}

static char *folder_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? strndup(path, (size_t)(slash - path)) : strdup(".");
}

static void test_spider_comes_back_whole(void **state)
{
    (void)state;
    const char *path = lmt_spider_path();
    if (!path)
        skip();
    size_t n = 0;
    uint8_t *data = read_whole(path, &n);
    char *dir = folder_of(path);
    lm_mesh *here = NULL, *there = NULL;
    assert_int_equal(lm_mesh_load(path, NULL, &here), LM_OK);
    assert_int_equal(lm_io_load_isolated(data, n, path, dir, NULL, &there), LM_OK);
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
    free(dir);
    free(data);
}

static void test_reader_error_comes_back(void **state)
{
    (void)state;
    const char *path = lmt_spider_path();
    if (!path)
        skip();
    size_t n = 0;
    uint8_t *data = read_whole(path, &n);
    char *dir = folder_of(path);
    lm_load_options few = {.max_tris = 10};
    lm_mesh *m = NULL;
    lm_status here = lm_mesh_load(path, &few, &m);
    assert_int_equal(here, LM_E_RANGE);
    char msg[512];
    snprintf(msg, sizeof msg, "%s", lm_last_error());
    lm_clear_error();
    assert_int_equal(lm_io_load_isolated(data, n, path, dir, &few, &m), here);
    assert_null(m);
    assert_string_equal(lm_last_error(), msg);
    free(dir);
    free(data);
}

/* A file assimp 5.2 crashes on: an LM_E_FORMAT error in one line, from the file and from memory. */
static void check_crash_input(const char *path, const char *ext)
{
    lm_mesh *m = NULL;
    lm_clear_error();
    assert_int_equal(lm_mesh_load(path, NULL, &m), LM_E_FORMAT);
    assert_null(m);
    assert_non_null(strstr(lm_last_error(), "the model reader"));
    assert_null(strchr(lm_last_error(), '\n'));
    size_t n = 0;
    uint8_t *data = read_whole(path, &n);
    assert_int_equal(lm_mesh_load_memory(data, n, ext, NULL, &m), LM_E_FORMAT);
    assert_null(m);
    assert_null(strchr(lm_last_error(), '\n'));
    free(data);
}

static void test_glb_null_read_is_an_error(void **state)
{
    (void)state;
    check_crash_input(LUMESH_TEST_DATA "/hostile/glb-assimp-null-read.glb", "glb");
}

static void test_fbx_abort_is_an_error(void **state)
{
    (void)state;
    char path[] = "/tmp/lumesh-fbx-XXXXXX.fbx";
    int fd = mkstemps(path, 4);
    assert_true(fd >= 0);
    size_t n = 0; /* the kept fuzz input; byte 0 is the fuzzer's format hint */
    uint8_t *data =
        read_whole(LUMESH_TEST_DATA "/../fuzz/corpus/mesh_load/regress_fbx_tokenizer_abort", &n);
    FILE *f = fdopen(fd, "wb");
    assert_int_equal(fwrite(data + 1, 1, n - 1, f), n - 1);
    fclose(f);
    check_crash_input(path, "fbx");
    unlink(path);
    free(data);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spider_comes_back_whole),
        cmocka_unit_test(test_reader_error_comes_back),
        cmocka_unit_test(test_glb_null_read_is_an_error),
        cmocka_unit_test(test_fbx_abort_is_an_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
