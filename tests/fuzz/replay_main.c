/* tests/fuzz/replay_main.c — a main() for a libFuzzer target built without libFuzzer: runs
 * LLVMFuzzerInitialize, then LLVMFuzzerTestOneInput once on every file named (a folder: each file
 * in it, in name order), so the normal build replays a target's corpus as a plain test
 * (tests/CMakeLists.txt: fuzz_replay_*). An input that breaks the target aborts, as it would under
 * libFuzzer; exit 0 and "replayed N inputs" otherwise; a file that cannot be read: one line, 1. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int replay_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        fprintf(stderr, "replay: cannot read '%s'\n", path);
        return 0;
    }
    size_t cap = 1 << 16, len = 0;
    uint8_t *buf = malloc(cap);
    for (size_t n; buf && (n = fread(buf + len, 1, cap - len, fp)) > 0;) {
        len += n;
        if (len == cap) {
            uint8_t *grown = realloc(buf, cap *= 2);
            if (!grown)
                free(buf);
            buf = grown;
        }
    }
    int ok = buf && !ferror(fp);
    fclose(fp);
    if (!ok) {
        free(buf);
        fprintf(stderr, "replay: cannot read '%s'\n", path);
        return 0;
    }
    LLVMFuzzerTestOneInput(buf, len);
    free(buf);
    return 1;
}

/* A file, or every regular file of a folder in name order; adds the inputs replayed to *count. */
static int replay_path(const char *path, int *count)
{
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        struct dirent **names;
        int n = scandir(path, &names, NULL, alphasort), ok = n >= 0;
        for (int i = 0; i < n; i++) {
            char full[4096];
            snprintf(full, sizeof full, "%s/%s", path, names[i]->d_name);
            if (ok && names[i]->d_name[0] != '.' && stat(full, &st) == 0 && S_ISREG(st.st_mode)) {
                ok = replay_file(full);
                *count += ok;
            }
            free(names[i]);
        }
        free(names);
        if (n < 0)
            fprintf(stderr, "replay: cannot list '%s'\n", path);
        return ok;
    }
    int ok = replay_file(path);
    *count += ok;
    return ok;
}

int main(int argc, char **argv)
{
    LLVMFuzzerInitialize(&argc, &argv);
    int count = 0;
    for (int i = 1; i < argc; i++)
        if (!replay_path(argv[i], &count))
            return 1;
    printf("replayed %d inputs\n", count);
    return 0;
}
