/* coordinator/quality/json_text.h — text of the JSON every command and file writes: a string
 * literal, quoted and escaped (in this room, below simplify/ and job/, so that both can use it). */
#ifndef LM_COORDINATOR_JSON_TEXT_H
#define LM_COORDINATOR_JSON_TEXT_H

#include <stdio.h>

/* JSON string literal (quoted and escaped) to fp. */
void co_json_string(FILE *fp, const char *s);

#endif
