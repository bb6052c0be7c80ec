/* common/optimizer/fiber.c — fibers (fiber.h): entered once with setcontext on a stack of
 * their own, then switched with _setjmp/_longjmp, which touch no signal mask (no system call,
 * unlike swapcontext), and announced to AddressSanitizer where it is built in. */
#undef _FORTIFY_SOURCE /* its longjmp check refuses a jump to another stack */
#include "common/optimizer/fiber.h"

#include <setjmp.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <ucontext.h>
#include <unistd.h>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LM_FIBER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define LM_FIBER_ASAN 1
#endif
#ifdef LM_FIBER_ASAN
#include <sanitizer/common_interface_defs.h>
#endif

struct lm_fiber {
    void *map; /* guard page, then the stack */
    size_t map_bytes;
    void *stack;
    size_t stack_bytes;
    ucontext_t start;
    jmp_buf self, caller;
    void (*fn)(void *arg);
    void *arg;
    int started, done;
    /* AddressSanitizer's bookkeeping of the two sides */
    void *fake_self, *fake_caller;
    const void *caller_bottom;
    size_t caller_bytes;
};

static _Thread_local lm_fiber *starting; /* handed to trampoline() across setcontext */

/* Leaving the current stack for [bottom, bottom + bytes); *fake keeps the leaving side's state
 * (NULL: the leaving side ends). */
static void leaving(void **fake, const void *bottom, size_t bytes)
{
#ifdef LM_FIBER_ASAN
    __sanitizer_start_switch_fiber(fake, bottom, bytes);
#else
    (void)fake, (void)bottom, (void)bytes;
#endif
}

/* Arrived on a stack whose state is fake; where we came from goes to *bottom, *bytes. */
static void arrived(void *fake, const void **bottom, size_t *bytes)
{
#ifdef LM_FIBER_ASAN
    __sanitizer_finish_switch_fiber(fake, bottom, bytes);
#else
    (void)fake, (void)bottom, (void)bytes;
#endif
}

static void trampoline(void)
{
    lm_fiber *f = starting;
    arrived(NULL, &f->caller_bottom, &f->caller_bytes);
    f->fn(f->arg);
    f->done = 1;
    leaving(NULL, f->caller_bottom, f->caller_bytes);
    _longjmp(f->caller, 1);
}

lm_status lm_fiber_create(size_t stack_bytes, void (*fn)(void *arg), void *arg, lm_fiber **out)
{
    *out = NULL;
    size_t page = (size_t)sysconf(_SC_PAGESIZE);
    if (stack_bytes < ((size_t)64 << 10))
        stack_bytes = (size_t)64 << 10;
    stack_bytes = (stack_bytes + page - 1) / page * page;
    lm_fiber *f = calloc(1, sizeof *f);
    if (!f)
        return lm_fail(LM_E_NOMEM, "out of memory for a fiber");
    f->map_bytes = stack_bytes + page;
    f->map = mmap(NULL, f->map_bytes, PROT_READ | PROT_WRITE,
                  MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE | MAP_STACK, -1, 0);
    if (f->map == MAP_FAILED || mprotect(f->map, page, PROT_NONE) != 0 ||
        getcontext(&f->start) != 0) {
        if (f->map != MAP_FAILED)
            munmap(f->map, f->map_bytes);
        free(f);
        return lm_fail(LM_E_NOMEM, "cannot map a fiber's stack of %zu bytes", stack_bytes);
    }
    f->stack = (char *)f->map + page;
    f->stack_bytes = stack_bytes;
    f->fn = fn;
    f->arg = arg;
    f->start.uc_stack.ss_sp = f->stack;
    f->start.uc_stack.ss_size = f->stack_bytes;
    f->start.uc_link = NULL;
    makecontext(&f->start, trampoline, 0);
    *out = f;
    return LM_OK;
}

void lm_fiber_destroy(lm_fiber *f)
{
    if (!f)
        return;
    munmap(f->map, f->map_bytes);
    free(f);
}

int lm_fiber_resume(lm_fiber *f)
{
    if (!_setjmp(f->caller)) {
        leaving(&f->fake_caller, f->stack, f->stack_bytes);
        if (!f->started) {
            f->started = 1;
            starting = f;
            setcontext(&f->start);
        }
        _longjmp(f->self, 1);
    }
    arrived(f->fake_caller, NULL, NULL);
    return f->done;
}

void lm_fiber_yield(lm_fiber *f)
{
    if (!_setjmp(f->self)) {
        leaving(&f->fake_self, f->caller_bottom, f->caller_bytes);
        _longjmp(f->caller, 1);
    }
    arrived(f->fake_self, &f->caller_bottom, &f->caller_bytes);
}
