/* tests/unit/test_support.h — helpers shared by unit tests: test-data paths, temp dirs, tiny
 * meshes. */
#ifndef LM_TEST_SUPPORT_H
#define LM_TEST_SUPPORT_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h> /* after the headers it needs */

#include "common/mesh.h"

/* Absolute path of a test-data file under tests/data (static buffer, one per call site is fine). */
const char *lmt_data_path(const char *rel);
/* Path of bunny00.off / spider.obj fetched by scripts/install-deps.sh (NULL if absent). */
const char *lmt_bunny_path(void);
const char *lmt_spider_path(void);
/* A fresh temporary directory (mkdtemp), removed by lmt_rmdir. */
char *lmt_mkdtemp(void);
void lmt_rmdir(char *dir);
/* A closed icosahedron-ish sphere (subdivided octahedron) with UVs, normals; level 0 = octahedron.
 */
lm_mesh *lmt_make_sphere(int subdivisions);
/* A flat n x n grid of vertices in z=0 (open, with boundary), UVs = xy. */
lm_mesh *lmt_make_grid(int n);
/* A uniform double in [0, 1) from xorshift64 state *s (nonzero), for reproducible random tests. */
double lmt_urand(uint64_t *s);

#endif
