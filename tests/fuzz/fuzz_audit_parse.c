/* tests/fuzz/fuzz_audit_parse.c — libFuzzer target for `--audit-lanes` text (co_audit_parse,
 * coordinator/views/lane_audit.h): any input (cut at its first NUL) gives LM_OK with P and R
 * within their limits, which printed as "P,R" (or "0" when off) parse back the same, or
 * LM_E_INVALID with a one-line message; never a crash or a leak. Seeds:
 * tests/fuzz/corpus/audit_parse/. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "coordinator/views/lane_audit.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    co_audit_rule r = {0, 0}, back = {1, 1};
    lm_status s = co_audit_parse(text, &r);
    free(text);
    if (s != LM_OK) {
        LM_ASSERT(s == LM_E_INVALID && lm_last_error()[0] != '\0' &&
                  !strchr(lm_last_error(), '\n'));
        return 0;
    }
    LM_ASSERT(r.probation <= CO_AUDIT_MAX_PROBATION && r.rate <= CO_AUDIT_MAX_RATE);
    char again[32];
    if (co_audit_off(r))
        snprintf(again, sizeof again, "0");
    else
        snprintf(again, sizeof again, "%u,%u", r.probation, r.rate);
    LM_ASSERT(co_audit_parse(again, &back) == LM_OK && back.probation == r.probation &&
              back.rate == r.rate);
    return 0;
}
