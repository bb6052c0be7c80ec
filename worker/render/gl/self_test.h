/* worker/render/gl/self_test.h — a small real rendering check of a GL context (used by
 * lumesh-worker
 * --self-test and the unit tests): clear + one triangle into an FBO, read back, check pixels. */
#ifndef LM_WORKER_SELF_TEST_H
#define LM_WORKER_SELF_TEST_H

#include "common/error.h"
#include "worker/render/gl/gl_context.h"

/* Makes ctx current and renders a 32x32 test image; LM_E_DEVICE naming the wrong pixel on
 * mismatch. *red_pixels (may be NULL) receives how many pixels the triangle covered. */
lm_status wk_self_test_run(wk_gl_context *ctx, int *red_pixels);

#endif
