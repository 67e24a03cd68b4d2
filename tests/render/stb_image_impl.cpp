// The one translation unit that holds stb_image's implementation (PNG reading in the tests).
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
