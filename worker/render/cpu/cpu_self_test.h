/* worker/render/cpu/cpu_self_test.h — the CPU rasteriser's self-test (the counterpart of
 * self_test.h). */
#ifndef LM_WORKER_CPU_SELF_TEST_H
#define LM_WORKER_CPU_SELF_TEST_H

#include "common/error.h"

/* Renders a red triangle over the lower-left half of a 32x32 view on the background grey and
 * checks every pixel (the diagonal may be either); *covered (may be NULL) = red pixels. */
lm_status wk_cpu_self_test_run(int *covered);

#endif
