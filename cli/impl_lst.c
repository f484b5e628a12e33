/* The lst.h implementation, in a translation unit of its own so that the
 * four compile in parallel. */
#define LST_IMPLEMENTATION
#include "../lst.h"
