/* common/optimizer/fiber.h — cooperative fibers on one thread: a function that runs on a
 * stack of its own and hands control back to whoever resumed it, so that code written as one
 * sequential call chain (a lane's edge optimisation, lanes.h) can pause in the middle of it
 * without a thread. A switch is a few dozen instructions in user space (no system call, no
 * scheduler, no processor woken), where a handoff between threads costs two futex calls and,
 * on a VM, often the wake-up of an idle processor.
 *
 * Contract:
 * - Blocking: lm_fiber_resume runs the fiber until it calls lm_fiber_yield (or its function
 *   returns) and only then returns; lm_fiber_yield returns when the fiber is next resumed.
 *   Nothing ever runs concurrently: fibers belong to the thread that created them.
 * - Failure: lm_fiber_create fails (LM_E_NOMEM) when the stack cannot be mapped; switching
 *   cannot fail. A fiber that overruns its stack hits a guard page (SIGSEGV), never another
 *   object.
 * - Ownership: lm_fiber_create makes a fiber (with its stack) that lm_fiber_destroy releases; a
 *   fiber may be destroyed whenever it is not running (suspended in lm_fiber_yield, finished or
 *   never started): what its stack still holds is dropped, so it must own nothing there.
 * - Sanitizers: switches are announced to AddressSanitizer (its fiber interface), so its stack
 *   checks follow every stack. */
#ifndef LM_COMMON_OPTIMIZER_FIBER_H
#define LM_COMMON_OPTIMIZER_FIBER_H

#include <stddef.h>

#include "common/error.h"

/* Stack of a lane's fiber: as much as a thread gets by default. Mapped lazily, so only the pages
 * a fiber touches are ever allocated. */
#define LM_FIBER_STACK_BYTES ((size_t)8 << 20)

typedef struct lm_fiber lm_fiber;

/* A fiber that will run fn(arg) on a stack of `stack_bytes` (at least 64 KiB) when first
 * resumed. */
lm_status lm_fiber_create(size_t stack_bytes, void (*fn)(void *arg), void *arg, lm_fiber **out);
void lm_fiber_destroy(lm_fiber *f);

/* From outside f: run it until it yields or its function returns; 1 when it has returned (it
 * must not be resumed again), else 0. */
int lm_fiber_resume(lm_fiber *f);

/* From inside f: back to where it was resumed from, until the next lm_fiber_resume. */
void lm_fiber_yield(lm_fiber *f);

#endif
