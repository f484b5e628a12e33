/* The lst.h implementation, in a translation unit of its own so that the
 * four compile in parallel. */
#define PW_THREADS /* rendering on every core (POSIX threads) */
#define LST_IMPLEMENTATION
#include "../lst.h"
