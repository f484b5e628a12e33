/* The tiled.h implementation, in a translation unit of its own so that the
 * four compile in parallel. */
#define PW_THREADS /* rendering and tile synthesis on every core (POSIX threads) */
#define TILED_IMPLEMENTATION
#include "../tiled.h"
