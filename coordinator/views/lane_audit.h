/* coordinator/views/lane_audit.h — the audit rule of --lanes remote (views_remote_lanes.c): which
 * lanes a second worker runs again, and what a tally of the result bytes decides. An honest lane
 * result is deterministic (the same request gives the same bytes on any honest worker), so two
 * results that differ mean a worker computed wrong. Pure functions: no I/O, no state.
 *
 * The rule: a worker is on probation until P of its results agreed with another worker's (every
 * lane it runs meanwhile is audited); after that a lane is audited when a hash of (the group's
 * start mesh hash, the lane's index) falls in 1 of R (the same lanes on every run of the job). A
 * mismatch goes to a third worker: the result two workers agree on is merged, the odd worker
 * fenced. Why P and R: coordinator/OPTIMIZER.md, "Lanes on workers", audits. */
#ifndef LM_COORDINATOR_VIEWS_LANE_AUDIT_H
#define LM_COORDINATOR_VIEWS_LANE_AUDIT_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

/* The defaults of --audit-lanes P,R (resolved by the job's resolve_options, nowhere else). */
#define CO_AUDIT_DEFAULT_PROBATION 4u
#define CO_AUDIT_DEFAULT_RATE 16u
#define CO_AUDIT_MAX_RATE 1000000u
#define CO_AUDIT_MAX_PROBATION 1000000u
/* The results of one lane compared at most: the first, the audit's, the arbiter's. */
#define CO_AUDIT_MAX_VOTES 3u

typedef struct co_audit_rule {
    uint32_t probation; /* results that must agree with another worker's before sampling: P */
    uint32_t rate;      /* then 1 lane in `rate` audited: R (0 = none after probation) */
} co_audit_rule;

/* "P,R" or "0" (off: no audit) into *out; LM_E_INVALID with a one-line message otherwise. */
lm_status co_audit_parse(const char *text, co_audit_rule *out);

/* 1: the rule audits nothing. */
int co_audit_off(co_audit_rule r);

/* 1: the result of lane `lane` of the group whose start mesh hashes to start_hash, run by a worker
 * of which `confirmed` results agreed with another worker's, is to be run again by another worker.
 */
int co_audit_wanted(co_audit_rule r, uint64_t confirmed, uint64_t start_hash, uint32_t lane);

typedef struct co_audit_vote {
    uint32_t worker; /* the worker's id (co_worker.id) */
    const uint8_t *bytes;
    size_t len;
} co_audit_vote;

typedef enum co_audit_verdict {
    CO_AUDIT_AGREED = 0, /* two results agree: *winner is one of them */
    CO_AUDIT_MORE,       /* no two agree yet: another worker's result is needed */
    CO_AUDIT_SPLIT,      /* CO_AUDIT_MAX_VOTES results, no two agree: nothing can be merged */
} co_audit_verdict;

/* What the n results of a lane (n >= 2) decide. With CO_AUDIT_AGREED, *winner is the index of the
 * first result that another equals; the votes unequal to it are the odd ones. */
co_audit_verdict co_audit_tally(const co_audit_vote *v, uint32_t n, uint32_t *winner);

/* 1: votes a and b carry the same bytes. */
int co_audit_same(const co_audit_vote *a, const co_audit_vote *b);

#endif
