/* coordinator/views/lane_audit.c — the audit rule of --lanes remote (lane_audit.h). */
#include "coordinator/views/lane_audit.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

static int parse_u32(const char *s, char **end, uint32_t hi, uint32_t *out)
{
    if (*s < '0' || *s > '9')
        return 0;
    errno = 0;
    unsigned long long v = strtoull(s, end, 10);
    if (errno || v > hi)
        return 0;
    *out = (uint32_t)v;
    return 1;
}

lm_status co_audit_parse(const char *text, co_audit_rule *out)
{
    co_audit_rule r = {0, 0};
    char *end = NULL;
    if (text && !strcmp(text, "0")) {
        *out = r;
        return LM_OK;
    }
    if (!text || !parse_u32(text, &end, CO_AUDIT_MAX_PROBATION, &r.probation) || *end != ',' ||
        !parse_u32(end + 1, &end, CO_AUDIT_MAX_RATE, &r.rate) || *end)
        return lm_fail(LM_E_INVALID,
                       "--audit-lanes expects P,R (P lanes of probation, then 1 in R; "
                       "P <= %u, R <= %u) or 0 (off), got '%.40s'",
                       CO_AUDIT_MAX_PROBATION, CO_AUDIT_MAX_RATE, text ? text : "");
    *out = r;
    return LM_OK;
}

int co_audit_off(co_audit_rule r)
{
    return !r.probation && !r.rate;
}

/* splitmix64's finaliser: every bit of x moves every bit of the result. */
static uint64_t mix(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

int co_audit_wanted(co_audit_rule r, uint64_t confirmed, uint64_t start_hash, uint32_t lane)
{
    if (confirmed < r.probation)
        return 1;
    return r.rate && mix(start_hash ^ mix(lane + 1ull)) % r.rate == 0;
}

int co_audit_same(const co_audit_vote *a, const co_audit_vote *b)
{
    return a->len == b->len && (!a->len || !memcmp(a->bytes, b->bytes, a->len));
}

co_audit_verdict co_audit_tally(const co_audit_vote *v, uint32_t n, uint32_t *winner)
{
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = i + 1; j < n; j++)
            if (co_audit_same(&v[i], &v[j])) {
                *winner = i;
                return CO_AUDIT_AGREED;
            }
    return n >= CO_AUDIT_MAX_VOTES ? CO_AUDIT_SPLIT : CO_AUDIT_MORE;
}
