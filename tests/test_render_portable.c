/* The renderer's tests with the portable C in place of the SSE2 paths
 * (PW_NO_SIMD), so that both are tested: see test_render.c. */
#define PW_NO_SIMD
#include "test_render.c"
