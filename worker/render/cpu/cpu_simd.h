/* worker/render/cpu/cpu_simd.h — four-lane float and int vectors for the CPU rasteriser's pixel
 * loops (GCC vector extensions: SSE2 on x86-64, NEON on AArch64, scalar code elsewhere). Every
 * operation is the IEEE (or two's complement) one lane by lane, so results never depend on the
 * target. */
#ifndef LM_WORKER_CPU_SIMD_H
#define LM_WORKER_CPU_SIMD_H

#include <stdint.h>

typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));

static inline v4f wk_v4_splat(float x)
{
    return (v4f){x, x, x, x};
}

#endif
