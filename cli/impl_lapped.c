/* The lapped.h implementation, in a translation unit of its own so that the
 * four compile in parallel. */
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"
