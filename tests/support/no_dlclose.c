/* tests/support/no_dlclose.c — LD_PRELOAD shim for sanitizer test runs: makes dlclose() a no-op so
 * that shared objects (Mesa's driver) stay mapped until exit. LeakSanitizer can then name the
 * module of allocations those objects leave behind, and tests/lsan.supp suppresses them by name;
 * without it they show as "<unknown module>" and cannot be told apart from ours. */
int dlclose(void *handle);

int dlclose(void *handle)
{
    (void)handle;
    return 0;
}
