/* tests/bench/bench_foundation.c — the foundation's costs at asset scale: generate the frog
 * (default 2,000,000 triangles), write it as GLB and OBJ, load each back, and simplify it with QEM
 * to 1% of its vertices. Every phase runs in its own forked child so its peak resident memory
 * (ru_maxrss from wait4) is its own; the parent stays small and does no mesh work.
 *
 * usage: bench_foundation [--tris N] [--dir DIR] [--keep]   prints a table, then one JSON line.
 * Files go to a fresh folder DIR/lumesh-bench-XXXXXX (DIR defaults to /tmp), removed at the end
 * unless --keep. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "common/io/mesh_io.h"
#include "coordinator/frog/frog.h"
#include "coordinator/simplify/simplify.h"

enum { PH_GENERATE, PH_SAVE, PH_LOAD_GLB, PH_LOAD_OBJ, PH_SIMPLIFY, PH_COUNT };
static const char *const phase_names[PH_COUNT] = {"generate", "save_glb_obj", "load_glb",
                                                  "load_obj", "simplify_qem_1pct"};

/* What a child reports through its pipe. */
typedef struct result {
    int status;           /* lm_status of the phase */
    double seconds;       /* the timed operation */
    double seconds2;      /* save: OBJ time (seconds is GLB) */
    uint32_t verts, tris; /* mesh the phase produced or read */
    char error[200];
    /* filled by the parent */
    long maxrss_kb;
} result;

typedef struct bench {
    uint32_t tris;
    const char *base;
    char dir[512], glb[600], obj[600];
} bench;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void note(result *r, lm_status s, const lm_mesh *m)
{
    r->status = s;
    if (s)
        snprintf(r->error, sizeof r->error, "%s", lm_last_error());
    if (m) {
        r->verts = m->live_verts;
        r->tris = m->live_tris;
    }
}

static void run_load(const char *path, result *r)
{
    lm_mesh *m = NULL;
    double t0 = now_s();
    lm_status s = lm_mesh_load(path, NULL, &m);
    r->seconds = now_s() - t0;
    note(r, s, m);
    lm_mesh_destroy(m);
}

/* The body of one phase, run in the child. */
static void run_phase(const bench *b, int phase, result *r)
{
    lm_mesh *m = NULL, *out = NULL;
    if (phase == PH_LOAD_GLB || phase == PH_LOAD_OBJ) {
        run_load(phase == PH_LOAD_GLB ? b->glb : b->obj, r);
        return;
    }
    double t0 = now_s();
    lm_status s = co_frog_generate(b->tris, 1, &m);
    double t1 = now_s();
    r->seconds = t1 - t0;
    if (!s && phase == PH_SAVE) {
        s = lm_mesh_save(b->glb, m);
        double t2 = now_s();
        r->seconds = t2 - t1;
        if (!s)
            s = lm_mesh_save(b->obj, m);
        r->seconds2 = now_s() - t2;
    } else if (!s && phase == PH_SIMPLIFY) {
        s = co_simplify(m, CO_SIMPLIFY_QEM, m->live_verts / 100, &out);
        r->seconds = now_s() - t1;
    }
    note(r, s, out ? out : m);
    lm_mesh_destroy(out);
    lm_mesh_destroy(m);
}

static int run_child(const bench *b, int phase, result *r)
{
    int fd[2];
    if (pipe(fd) != 0)
        return -1;
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        close(fd[0]);
        result mine;
        memset(&mine, 0, sizeof mine);
        run_phase(b, phase, &mine);
        ssize_t w = write(fd[1], &mine, sizeof mine);
        _exit(w == (ssize_t)sizeof mine ? 0 : 3);
    }
    close(fd[1]);
    memset(r, 0, sizeof *r);
    ssize_t got = read(fd[0], r, sizeof *r);
    close(fd[0]);
    int wstatus = 0;
    struct rusage ru;
    if (wait4(pid, &wstatus, 0, &ru) != pid)
        return -1;
    r->maxrss_kb = ru.ru_maxrss;
    if (got != (ssize_t)sizeof *r) {
        r->status = -1;
        snprintf(r->error, sizeof r->error, "child died (status 0x%x)", wstatus);
    }
    return 0;
}

static long file_kb(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)(st.st_size / 1024) : -1;
}

static void print_table(const bench *b, const result *r)
{
    printf("bench_foundation: frog %u triangles target, files in %s\n", b->tris, b->dir);
    printf("%-18s %10s %10s %10s %12s %10s  %s\n", "phase", "seconds", "verts", "tris",
           "peak_rss_MB", "B/tri", "note");
    for (int p = 0; p < PH_COUNT; p++) {
        double mb = r[p].maxrss_kb / 1024.0;
        char extra[300] = "";
        if (p == PH_SAVE)
            snprintf(extra, sizeof extra, "glb %.2f s (%ld KB), obj %.2f s (%ld KB)", r[p].seconds,
                     file_kb(b->glb), r[p].seconds2, file_kb(b->obj));
        if (r[p].status)
            snprintf(extra, sizeof extra, "FAILED: %s", r[p].error);
        double secs = p == PH_SAVE ? r[p].seconds + r[p].seconds2 : r[p].seconds;
        printf("%-18s %10.3f %10u %10u %12.1f %10.0f  %s\n", phase_names[p], secs, r[p].verts,
               r[p].tris, mb, b->tris ? r[p].maxrss_kb * 1024.0 / b->tris : 0.0, extra);
    }
}

static void print_json(const bench *b, const result *r)
{
    printf("{\"bench\":\"foundation\",\"tris_target\":%u,\"glb_kb\":%ld,\"obj_kb\":%ld,"
           "\"phases\":[",
           b->tris, file_kb(b->glb), file_kb(b->obj));
    for (int p = 0; p < PH_COUNT; p++)
        printf("%s{\"phase\":\"%s\",\"ok\":%s,\"seconds\":%.4f,\"seconds_obj\":%.4f,"
               "\"verts\":%u,\"tris\":%u,\"peak_rss_kb\":%ld}",
               p ? "," : "", phase_names[p], r[p].status ? "false" : "true", r[p].seconds,
               r[p].seconds2, r[p].verts, r[p].tris, r[p].maxrss_kb);
    printf("]}\n");
}

static int parse(int argc, char **argv, bench *b, int *keep)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--tris") && i + 1 < argc) {
            b->tris = (uint32_t)strtoul(argv[++i], NULL, 10);
        } else if (!strcmp(argv[i], "--dir") && i + 1 < argc) {
            b->base = argv[++i];
        } else if (!strcmp(argv[i], "--keep")) {
            *keep = 1;
        } else {
            fprintf(stderr, "usage: bench_foundation [--tris N] [--dir DIR] [--keep]\n");
            return 1;
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    bench b = {.tris = 2000000};
    int keep = 0;
    if (parse(argc, argv, &b, &keep))
        return 1;
    snprintf(b.dir, sizeof b.dir, "%s/lumesh-bench-XXXXXX", b.base ? b.base : "/tmp");
    if (!mkdtemp(b.dir)) {
        perror("bench_foundation: mkdtemp");
        return 2;
    }
    snprintf(b.glb, sizeof b.glb, "%s/frog.glb", b.dir);
    snprintf(b.obj, sizeof b.obj, "%s/frog.obj", b.dir);
    result r[PH_COUNT];
    int failed = 0;
    for (int p = 0; p < PH_COUNT; p++) {
        if (run_child(&b, p, &r[p]) != 0) {
            perror("bench_foundation: fork/wait");
            return 2;
        }
        failed |= r[p].status != 0;
    }
    print_table(&b, r);
    print_json(&b, r);
    if (!keep) {
        char cmd[700];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", b.dir);
        if (system(cmd) != 0)
            fprintf(stderr, "bench_foundation: could not remove %s\n", b.dir);
    }
    return failed ? 1 : 0;
}
