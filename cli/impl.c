/* The one translation unit that compiles the libraries' implementations. */
#define PATCHWORK_IMPLEMENTATION
#include "../tiled.h"
#include "../lapped.h"
#include "../pgp.h"
#include "../lst.h"
