/* The one translation unit that compiles the libraries' implementations. */
#define PATCHWORK_IMPLEMENTATION
#include "../tiled.h"
