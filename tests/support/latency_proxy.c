/* tests/support/latency_proxy.c — a TCP proxy that adds latency in user space, for kernels without
 * the netem qdisc (issue 36: the coordinator's round trips to cluster workers at 100 µs).
 *
 *   latency_proxy --listen HOST:PORT --connect HOST:PORT --delay-us D [--spin-us S]
 *                 [--port-file F]
 *
 * Every connection accepted at --listen gets its own connection to --connect; each chunk read from
 * either side is held D µs from the moment it was read, then written to the other side, in order.
 * So a round trip through the proxy takes 2·D more than without it. One thread, epoll: a queue of
 * chunks per direction stamped with their arrival time; the loop sleeps (epoll_pwait2, timer slack
 * of 1 ns) until S µs before the next chunk is due and spins the last S µs (default 50), because a
 * VM's sleeping processor wakes tens of µs late. Buffering is bounded (1 MiB a direction): a side
 * whose queue is full is not read until it drains, and a slow reader never blocks the others.
 * A half-close (EOF from one side) is passed on as shutdown(SHUT_WR) once that direction's queue is
 * written; a reset or error on either side resets the other (SO_LINGER 0) and frees the pair.
 * With PORT 0 the kernel picks the port; --port-file F then receives it (written atomically), so
 * tests need no fixed ports. Bad flags: one line on stderr, exit 1. Runs until killed.
 * Used by tests/integration/latency_proxy.sh and scripts/latency-check.sh. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

enum {
    CHUNK_MAX = 64 * 1024,   /* the most one read takes */
    QUEUE_MAX = 1024 * 1024, /* bytes held per direction before its source is not read */
    EVENTS_MAX = 64,
};

typedef struct chunk {
    struct chunk *next;
    int64_t due_ns; /* when it may be written: its arrival plus the delay */
    size_t len, off;
    unsigned char data[];
} chunk;

/* One direction of a pair: bytes read from side `from` and written to the other side. */
typedef struct direction {
    chunk *head, *tail;
    size_t bytes;
    int eof;     /* the source said EOF; shut the destination's writing once the queue is empty */
    int shut;    /* the destination's writing is shut */
    int blocked; /* the destination answered EAGAIN: wait for EPOLLOUT */
} direction;

struct pair;
typedef struct end {
    struct pair *pair;
    int side; /* 0 the accepted client, 1 the connection to --connect */
} end;

typedef struct pair {
    int fd[2];
    uint32_t mask[2]; /* the epoll events each fd is registered for */
    end ends[2];
    direction dir[2]; /* dir[s]: read from side s, written to side 1 - s */
    int gone[2];      /* the fd is out of epoll: read to EOF and its writing shut */
    int connecting;   /* the connection to --connect is not established yet */
    int dead;
    struct pair *next;
} pair;

typedef struct proxy {
    int ep, listener;
    struct addrinfo *upstream;
    int64_t delay_ns, spin_ns;
    pair *pairs;
} proxy;

static void die(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("latency_proxy: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    exit(1);
}

static int64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* --- options --- */

typedef struct options {
    const char *listen, *connect, *port_file;
    long delay_us, spin_us;
} options;

static long parse_us(const char *flag, const char *s)
{
    char *endp;
    errno = 0;
    long v = strtol(s, &endp, 10);
    if (errno || endp == s || *endp || v < 0 || v > 10000000)
        die("%s '%s': expected microseconds, 0 to 10000000", flag, s);
    return v;
}

#define USAGE "--listen HOST:PORT --connect HOST:PORT --delay-us D [--spin-us S] [--port-file F]"

static options parse_options(int argc, char **argv)
{
    static const char *const flags[] = {"--listen", "--connect", "--port-file", "--delay-us",
                                        "--spin-us"};
    options o = {.delay_us = -1, .spin_us = 50};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        int f = 0;
        while (f < 5 && strcmp(a, flags[f]))
            f++;
        if (f == 5)
            die("unknown option '%s' (usage: latency_proxy " USAGE ")", a);
        if (i + 1 >= argc)
            die("%s needs a value (usage: latency_proxy " USAGE ")", a);
        const char *v = argv[++i];
        if (f == 0)
            o.listen = v;
        else if (f == 1)
            o.connect = v;
        else if (f == 2)
            o.port_file = v;
        else if (f == 3)
            o.delay_us = parse_us(a, v);
        else
            o.spin_us = parse_us(a, v);
    }
    if (!o.listen || !o.connect || o.delay_us < 0)
        die("--listen, --connect and --delay-us are required (usage: latency_proxy " USAGE ")");
    return o;
}

/* HOST:PORT (HOST may be [v6]) to addresses; `passive` for a listening socket. */
static struct addrinfo *resolve(const char *flag, const char *hostport, int passive)
{
    const char *colon = strrchr(hostport, ':');
    if (!colon || colon == hostport || !colon[1])
        die("%s '%s': expected HOST:PORT", flag, hostport);
    char host[256];
    size_t n = (size_t)(colon - hostport);
    if (hostport[0] == '[' && n >= 2 && hostport[n - 1] == ']') {
        hostport++;
        n -= 2;
    }
    if (n >= sizeof host)
        die("%s '%s': the host is too long", flag, hostport);
    memcpy(host, hostport, n);
    host[n] = '\0';
    struct addrinfo hints = {.ai_socktype = SOCK_STREAM, .ai_flags = passive ? AI_PASSIVE : 0};
    struct addrinfo *res = NULL;
    int rc = getaddrinfo(host, colon + 1, &hints, &res);
    if (rc)
        die("%s '%s': %s", flag, hostport, gai_strerror(rc));
    return res;
}

/* --- sockets --- */

static void set_nodelay(int fd)
{
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

static int open_listener(const char *hostport, const char *port_file)
{
    struct addrinfo *ai = resolve("--listen", hostport, 1);
    int fd = socket(ai->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    int one = 1;
    if (fd < 0 || setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) ||
        bind(fd, ai->ai_addr, ai->ai_addrlen) || listen(fd, 128))
        die("--listen '%s': %s", hostport, strerror(errno));
    freeaddrinfo(ai);
    if (port_file) {
        struct sockaddr_storage ss;
        socklen_t len = sizeof ss;
        if (getsockname(fd, (struct sockaddr *)&ss, &len))
            die("--listen '%s': %s", hostport, strerror(errno));
        int port = ntohs(ss.ss_family == AF_INET6 ? ((struct sockaddr_in6 *)&ss)->sin6_port
                                                  : ((struct sockaddr_in *)&ss)->sin_port);
        char tmp[PATH_MAX];
        snprintf(tmp, sizeof tmp, "%s.tmp", port_file);
        FILE *fp = fopen(tmp, "w");
        if (!fp || fprintf(fp, "%d\n", port) < 0 || fclose(fp) || rename(tmp, port_file))
            die("--port-file '%s': %s", port_file, strerror(errno));
    }
    return fd;
}

static void watch(proxy *px, pair *p, int side, uint32_t mask)
{
    if (p->mask[side] == mask)
        return;
    struct epoll_event ev = {.events = mask, .data.ptr = &p->ends[side]};
    epoll_ctl(px->ep, EPOLL_CTL_MOD, p->fd[side], &ev);
    p->mask[side] = mask;
}

/* The events each side waits for: readable while its outgoing queue has room, writable while its
 * incoming chunks wait for room in the kernel (or while the upstream connection is made). A side
 * read to EOF whose writing is shut leaves epoll (it would report EPOLLHUP for ever). */
static void rewatch(proxy *px, pair *p)
{
    for (int s = 0; s < 2; s++) {
        const direction *out = &p->dir[s], *in = &p->dir[1 - s];
        if (out->eof && in->shut) {
            if (!p->gone[s])
                epoll_ctl(px->ep, EPOLL_CTL_DEL, p->fd[s], NULL);
            p->gone[s] = 1;
            continue;
        }
        uint32_t mask = 0;
        if (!out->eof && out->bytes < QUEUE_MAX)
            mask |= EPOLLIN;
        if (in->blocked || (s == 1 && p->connecting))
            mask |= EPOLLOUT;
        watch(px, p, s, mask);
    }
}

static void free_queue(direction *d)
{
    for (chunk *c = d->head, *n; c; c = n) {
        n = c->next;
        free(c);
    }
    d->head = d->tail = NULL;
    d->bytes = 0;
}

/* Both sides closed; `reset` closes them with SO_LINGER 0 (an RST), passing a reset on. */
static void kill_pair(proxy *px, pair *p, int reset)
{
    if (p->dead)
        return;
    for (int s = 0; s < 2; s++) {
        if (reset) {
            struct linger lg = {.l_onoff = 1, .l_linger = 0};
            setsockopt(p->fd[s], SOL_SOCKET, SO_LINGER, &lg, sizeof lg);
        }
        if (!p->gone[s])
            epoll_ctl(px->ep, EPOLL_CTL_DEL, p->fd[s], NULL);
        close(p->fd[s]);
        free_queue(&p->dir[s]);
    }
    p->dead = 1;
}

static void add_fd(proxy *px, pair *p, int side)
{
    struct epoll_event ev = {.events = 0, .data.ptr = &p->ends[side]};
    if (epoll_ctl(px->ep, EPOLL_CTL_ADD, p->fd[side], &ev))
        die("epoll_ctl: %s", strerror(errno));
}

static void accept_all(proxy *px)
{
    for (;;) {
        int cfd = accept4(px->listener, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (cfd < 0)
            return; /* EAGAIN, or a connection that went before it was taken */
        const struct addrinfo *ai = px->upstream;
        int ufd = socket(ai->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
        if (ufd < 0 || (connect(ufd, ai->ai_addr, ai->ai_addrlen) && errno != EINPROGRESS)) {
            fprintf(stderr, "latency_proxy: cannot connect upstream: %s\n", strerror(errno));
            if (ufd >= 0)
                close(ufd);
            close(cfd);
            continue;
        }
        set_nodelay(cfd);
        set_nodelay(ufd);
        pair *p = calloc(1, sizeof *p);
        if (!p)
            die("out of memory");
        p->fd[0] = cfd;
        p->fd[1] = ufd;
        p->connecting = 1;
        for (int s = 0; s < 2; s++) {
            p->ends[s] = (end){.pair = p, .side = s};
            add_fd(px, p, s);
        }
        p->next = px->pairs;
        px->pairs = p;
        rewatch(px, p);
    }
}

/* --- the two directions --- */

/* Reads what side `s` has (until EAGAIN or a full queue), each read a chunk due after the delay. */
static void read_side(proxy *px, pair *p, int s)
{
    direction *d = &p->dir[s];
    static unsigned char buf[CHUNK_MAX];
    while (!d->eof && d->bytes < QUEUE_MAX) {
        ssize_t n = recv(p->fd[s], buf, sizeof buf, 0);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            return;
        if (n < 0) {
            kill_pair(px, p, 1);
            return;
        }
        if (n == 0) {
            d->eof = 1;
            return;
        }
        chunk *c = malloc(sizeof *c + (size_t)n);
        if (!c)
            die("out of memory");
        memcpy(c->data, buf, (size_t)n);
        c->len = (size_t)n;
        c->off = 0;
        c->due_ns = now_ns() + px->delay_ns;
        c->next = NULL;
        if (d->tail)
            d->tail->next = c;
        else
            d->head = c;
        d->tail = c;
        d->bytes += (size_t)n;
    }
}

/* Writes direction `s`'s due chunks to the other side; passes an EOF on once the queue is empty. */
static void flush_dir(proxy *px, pair *p, int s, int64_t now)
{
    direction *d = &p->dir[s];
    int to = p->fd[1 - s];
    if (p->connecting || d->blocked)
        return;
    while (d->head && d->head->due_ns <= now) {
        chunk *c = d->head;
        ssize_t n = send(to, c->data + c->off, c->len - c->off, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            d->blocked = 1;
            return;
        }
        if (n < 0) {
            kill_pair(px, p, 1);
            return;
        }
        c->off += (size_t)n;
        d->bytes -= (size_t)n;
        if (c->off < c->len)
            continue;
        d->head = c->next;
        if (!d->head)
            d->tail = NULL;
        free(c);
    }
    if (!d->head && d->eof && !d->shut) {
        shutdown(to, SHUT_WR);
        d->shut = 1;
    }
}

static void finish_connect(proxy *px, pair *p)
{
    int err = 0;
    socklen_t len = sizeof err;
    if (getsockopt(p->fd[1], SOL_SOCKET, SO_ERROR, &err, &len) || err) {
        fprintf(stderr, "latency_proxy: cannot connect upstream: %s\n",
                strerror(err ? err : errno));
        kill_pair(px, p, 1);
        return;
    }
    p->connecting = 0;
}

static void on_event(proxy *px, end *e, uint32_t events)
{
    pair *p = e->pair;
    int s = e->side;
    if (p->dead)
        return;
    if (s == 1 && p->connecting) {
        if (events & (EPOLLOUT | EPOLLERR | EPOLLHUP))
            finish_connect(px, p);
        if (p->dead || p->connecting)
            return;
    }
    if (events & EPOLLERR) { /* a reset: passed on to the other side */
        kill_pair(px, p, 1);
        return;
    }
    if ((events & EPOLLHUP) && p->dir[s].eof && !p->dir[1 - s].shut) {
        /* Closed (reset or timed out) before its queued bytes were due: they cannot be delivered,
         * and epoll would report the hang-up on every wait until they were (a busy loop). */
        kill_pair(px, p, 1);
        return;
    }
    if (events & EPOLLOUT)
        p->dir[1 - s].blocked = 0;
    if (events & (EPOLLIN | EPOLLHUP))
        read_side(px, p, s);
}

/* Writes every due chunk, passes EOFs on, frees pairs that are done; returns the earliest time a
 * queued chunk is due (INT64_MAX when none waits on time alone). */
static int64_t service(proxy *px)
{
    int64_t now = now_ns(), next = INT64_MAX;
    for (pair **pp = &px->pairs; *pp;) {
        pair *p = *pp;
        for (int s = 0; s < 2 && !p->dead; s++)
            flush_dir(px, p, s, now);
        if (!p->dead && p->dir[0].shut && p->dir[1].shut)
            kill_pair(px, p, 0);
        if (p->dead) {
            *pp = p->next;
            free(p);
            continue;
        }
        rewatch(px, p);
        for (int s = 0; s < 2; s++) {
            const direction *d = &p->dir[s];
            if (d->head && !d->blocked && !p->connecting && d->head->due_ns < next)
                next = d->head->due_ns;
        }
        pp = &p->next;
    }
    return next;
}

/* Sleeps until `spin` before `due` (or an event), then spins: epoll with no timeout. */
static int wait_events(proxy *px, struct epoll_event *evs, int64_t due)
{
    int64_t left = due == INT64_MAX ? -1 : due - now_ns();
    if (left < 0 && due != INT64_MAX)
        left = 0;
    if (left > px->spin_ns) {
        int64_t sleep_ns = left - px->spin_ns;
        struct timespec ts = {.tv_sec = sleep_ns / 1000000000, .tv_nsec = sleep_ns % 1000000000};
        return epoll_pwait2(px->ep, evs, EVENTS_MAX, &ts, NULL);
    }
    if (left < 0)
        return epoll_pwait2(px->ep, evs, EVENTS_MAX, NULL, NULL);
    struct timespec zero = {0, 0};
    return epoll_pwait2(px->ep, evs, EVENTS_MAX, &zero, NULL);
}

int main(int argc, char **argv)
{
    options o = parse_options(argc, argv);
    signal(SIGPIPE, SIG_IGN);
    prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0); /* wake-ups on time, not up to 50 µs late */
    proxy px = {.delay_ns = o.delay_us * 1000, .spin_ns = o.spin_us * 1000};
    px.upstream = resolve("--connect", o.connect, 0);
    px.listener = open_listener(o.listen, o.port_file);
    px.ep = epoll_create1(EPOLL_CLOEXEC);
    struct epoll_event lev = {.events = EPOLLIN, .data.ptr = NULL};
    if (px.ep < 0 || epoll_ctl(px.ep, EPOLL_CTL_ADD, px.listener, &lev))
        die("epoll: %s", strerror(errno));
    struct epoll_event evs[EVENTS_MAX];
    for (;;) {
        int64_t due = service(&px);
        int n = wait_events(&px, evs, due);
        if (n < 0 && errno != EINTR)
            die("epoll_pwait2: %s", strerror(errno));
        for (int i = 0; i < n; i++) {
            if (!evs[i].data.ptr)
                accept_all(&px);
            else
                on_event(&px, evs[i].data.ptr, evs[i].events);
        }
    }
}
