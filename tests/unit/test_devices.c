/* tests/unit/test_devices.c — EGL device listing and choice, the --device policy (cpu, auto's
 * fallback), GL contexts (twice, two at once, on another thread), the rendering self-tests (GL
 * and CPU), and the USB accelerator table. */
#include "test_support.h"

#include <EGL/egl.h>
#include <pthread.h>
#include <string.h>

#include "worker/render/cpu/cpu_self_test.h"
#include "worker/render/device_choice.h"
#include "worker/render/gl/gl_context.h"
#include "worker/render/gl/self_test.h"
#include "worker/render/usb_devices.h"

static void test_list_devices(void **state)
{
    (void)state;
    wk_device_info devs[WK_MAX_DEVICES];
    int n = -1, software = 0, seen_software = 0;
    assert_int_equal(wk_egl_list_devices(devs, WK_MAX_DEVICES, &n), LM_OK);
    assert_true(n >= 1 && n <= WK_MAX_DEVICES);
    for (int i = 0; i < n; i++) {
        assert_true(devs[i].index >= 0 && devs[i].index < n);
        if (devs[i].is_software) {
            seen_software = 1;
            software += devs[i].usable;
            assert_true(devs[i].usable);
            assert_non_null(strstr(devs[i].renderer, "OpenGL ES 3"));
        } else {
            assert_false(seen_software); /* GPUs come first */
        }
    }
    assert_true(software >= 1); /* Mesa's llvmpipe is a dependency */
    int one = -1;               /* capacity is respected */
    assert_int_equal(wk_egl_list_devices(devs, 1, &one), LM_OK);
    assert_int_equal(one, 1);
}

static void test_bad_specs(void **state)
{
    (void)state;
    wk_gl_context *ctx = (wk_gl_context *)&ctx; /* must be reset to NULL on failure */
    assert_int_equal(wk_gl_context_create("egl:99", &ctx), LM_E_RANGE);
    assert_null(ctx);
    assert_non_null(strstr(lm_last_error(), "egl:99"));
    static const char *const bad[] = {"", "gpu", "egl:", "egl:x", "egl:-1", "egl:1x", "HOST"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(wk_gl_context_create(bad[i], &ctx), LM_E_INVALID);
        assert_non_null(strstr(lm_last_error(), "expected auto, host or egl:N"));
    }
}

static void test_choose_logic(void **state)
{
    (void)state;
    wk_device_info d[3];
    memset(d, 0, sizeof d);
    d[0] = (wk_device_info){.index = 2, .is_software = 0, .usable = 0};
    d[1] = (wk_device_info){.index = 0, .is_software = 0, .usable = 1};
    d[2] = (wk_device_info){.index = 1, .is_software = 1, .usable = 1};
    int i = -1;
    assert_int_equal(wk_egl_choose_device("auto", d, 3, &i), LM_OK);
    assert_int_equal(i, 1); /* first usable GPU */
    assert_int_equal(wk_egl_choose_device(NULL, d, 3, &i), LM_OK);
    assert_int_equal(i, 1);
    assert_int_equal(wk_egl_choose_device("host", d, 3, &i), LM_OK);
    assert_int_equal(i, 2);
    assert_int_equal(wk_egl_choose_device("egl:1", d, 3, &i), LM_OK);
    assert_int_equal(i, 2); /* N is EGL's index, not the position in the list */
    assert_int_equal(wk_egl_choose_device("egl:2", d, 3, &i), LM_E_DEVICE); /* unusable */
    assert_int_equal(wk_egl_choose_device("egl:7", d, 3, &i), LM_E_RANGE);
    d[1].usable = 0;
    assert_int_equal(wk_egl_choose_device("auto", d, 3, &i), LM_OK);
    assert_int_equal(i, 2); /* no working GPU: software */
    assert_int_equal(wk_egl_choose_device("host", d, 2, &i), LM_E_UNSUPPORTED);
    assert_int_equal(wk_egl_choose_device("auto", d, 2, &i), LM_E_DEVICE);
}

/* The --device policy above EGL: "cpu" is always there, "auto" is the first working GPU, else
 * "cpu" (never llvmpipe), the rest are EGL's. */
static void test_device_policy(void **state)
{
    (void)state;
    static const char *const good[] = {"cpu", "auto", "host", "egl:0", "egl:12"};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++)
        assert_int_equal(wk_device_check_spec(good[i]), LM_OK);
    assert_int_equal(wk_device_check_spec(NULL), LM_OK);
    static const char *const bad[] = {"", "gpu", "CPU", "cpu:0", "egl:", "egl:x"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(wk_device_check_spec(bad[i]), LM_E_INVALID);
        assert_non_null(strstr(lm_last_error(), "expected auto, cpu, host or egl:N"));
    }
    wk_device_info d[3];
    memset(d, 0, sizeof d);
    d[0] = (wk_device_info){.index = 2, .is_software = 0, .usable = 0};
    d[1] = (wk_device_info){.index = 0, .is_software = 0, .usable = 1};
    d[2] = (wk_device_info){.index = 1, .is_software = 1, .usable = 1};
    int i = 7;
    assert_int_equal(wk_device_choose("auto", d, 3, &i), LM_OK);
    assert_int_equal(i, 1); /* first usable GPU */
    assert_int_equal(wk_device_choose("cpu", d, 3, &i), LM_OK);
    assert_int_equal(i, -1);
    assert_int_equal(wk_device_choose("host", d, 3, &i), LM_OK);
    assert_int_equal(i, 2);
    d[1].usable = 0;
    assert_int_equal(wk_device_choose("auto", d, 3, &i), LM_OK);
    assert_int_equal(i, -1); /* no working GPU: the CPU rasteriser, not llvmpipe */
    assert_int_equal(wk_device_choose("auto", NULL, 0, &i), LM_OK);
    assert_int_equal(i, -1);
    assert_int_equal(wk_device_choose("gpu", d, 3, &i), LM_E_INVALID);
    wk_gl_context *ctx = (wk_gl_context *)&ctx;
    assert_int_equal(wk_device_open("cpu", &ctx), LM_OK);
    assert_null(ctx); /* the CPU rasteriser needs no context */
    assert_int_equal(wk_device_open("host", &ctx), LM_OK);
    assert_non_null(ctx);
    wk_gl_context_destroy(ctx);
}

static void test_host_context_twice(void **state)
{
    (void)state;
    for (int round = 0; round < 2; round++) {
        wk_gl_context *ctx = NULL;
        int red = 0;
        assert_int_equal(wk_gl_context_create("host", &ctx), LM_OK);
        assert_non_null(ctx);
        assert_true(eglGetCurrentContext() != EGL_NO_CONTEXT); /* create leaves it current */
        assert_int_equal(strncmp(wk_gl_context_description(ctx), "EGL device ", 11), 0);
        assert_int_equal(wk_gl_context_make_current(ctx), LM_OK);
        assert_int_equal(wk_self_test_run(ctx, &red), LM_OK);
        assert_true(red >= 496 && red <= 528);
        wk_gl_context_destroy(ctx);
        assert_true(eglGetCurrentContext() == EGL_NO_CONTEXT);
    }
    wk_gl_context_destroy(NULL);
}

static void test_two_contexts(void **state)
{
    (void)state;
    wk_gl_context *a = NULL, *b = NULL;
    assert_int_equal(wk_gl_context_create("host", &a), LM_OK);
    assert_int_equal(wk_gl_context_create("auto", &b), LM_OK);
    assert_int_equal(wk_self_test_run(a, NULL), LM_OK);
    assert_int_equal(wk_self_test_run(b, NULL), LM_OK);
    EGLContext current = eglGetCurrentContext();
    wk_device_info devs[WK_MAX_DEVICES];
    int n = 0; /* probing devices must not disturb the current context */
    assert_int_equal(wk_egl_list_devices(devs, WK_MAX_DEVICES, &n), LM_OK);
    assert_true(eglGetCurrentContext() == current);
    wk_gl_context_destroy(a); /* b shares the display: it must survive a's eglTerminate path */
    assert_int_equal(wk_self_test_run(b, NULL), LM_OK);
    wk_gl_context_destroy(b);
}

static void *thread_body(void *arg)
{
    wk_gl_context *ctx = NULL;
    lm_status *st = arg;
    *st = wk_gl_context_create("host", &ctx);
    if (*st == LM_OK)
        *st = wk_self_test_run(ctx, NULL);
    wk_gl_context_destroy(ctx);
    return NULL;
}

static void test_context_per_thread(void **state)
{
    (void)state;
    wk_gl_context *main_ctx = NULL;
    lm_status thread_status = LM_E_INTERNAL;
    pthread_t t;
    assert_int_equal(wk_gl_context_create("host", &main_ctx), LM_OK);
    assert_int_equal(pthread_create(&t, NULL, thread_body, &thread_status), 0);
    assert_int_equal(pthread_join(t, NULL), 0);
    assert_int_equal(thread_status, LM_OK);
    assert_int_equal(wk_self_test_run(main_ctx, NULL), LM_OK);
    wk_gl_context_destroy(main_ctx);
}

static void test_cpu_self_test(void **state)
{
    (void)state;
    int red = 0;
    assert_int_equal(wk_cpu_self_test_run(&red), LM_OK);
    assert_int_equal(red, 496); /* centres on the hypotenuse (a right edge) are left out */
}

static void test_usb(void **state)
{
    (void)state;
    wk_usb_device devs[WK_MAX_USB_DEVICES];
    int n = -1;
    assert_int_equal(wk_usb_list_devices(devs, WK_MAX_USB_DEVICES, &n), LM_OK);
    assert_true(n >= 0 && n <= WK_MAX_USB_DEVICES); /* zero without a USB bus */
    for (int i = 0; i < n; i++)
        assert_int_equal(devs[i].is_accelerator,
                         wk_usb_accelerator_name(devs[i].vendor_id, devs[i].product_id) != NULL);
    assert_int_equal(wk_usb_list_devices(NULL, 0, &n), LM_OK);
    assert_int_equal(n, 0);
    assert_non_null(strstr(wk_usb_accelerator_name(0x03e7, 0x2485), "Myriad X"));
    assert_non_null(strstr(wk_usb_accelerator_name(0x18d1, 0x9302), "Edge TPU"));
    assert_non_null(strstr(wk_usb_accelerator_name(0x17e9, 0x4301), "DisplayLink"));
    assert_null(wk_usb_accelerator_name(0x03e7, 0x0001));
    assert_null(wk_usb_accelerator_name(0x1d6b, 0x0002)); /* Linux root hub */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_list_devices),
        cmocka_unit_test(test_bad_specs),
        cmocka_unit_test(test_choose_logic),
        cmocka_unit_test(test_device_policy),
        cmocka_unit_test(test_host_context_twice),
        cmocka_unit_test(test_two_contexts),
        cmocka_unit_test(test_context_per_thread),
        cmocka_unit_test(test_cpu_self_test),
        cmocka_unit_test(test_usb),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
