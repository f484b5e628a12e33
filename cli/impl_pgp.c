/* The pgp.h implementation, in a translation unit of its own so that the
 * four compile in parallel. */
#define PW_THREADS /* rendering, tile synthesis and the solves on every core (POSIX threads) */
#define PGP_IMPLEMENTATION
#include "../pgp.h"
