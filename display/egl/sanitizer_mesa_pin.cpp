// Linked into every executable and test that makes an EGL context, in sanitizer builds only
// (kerf_pin_mesa_for_sanitizers() in display/egl/CMakeLists.txt): Mesa's llvmpipe driver
// (swrast_dri.so, loaded by EGL) keeps two 56-byte blocks per context that has drawn referenced
// from its own globals, and is unloaded by eglTerminate(), so LeakSanitizer then sees them
// unreferenced and reports them from "<unknown module>" (nothing can suppress that by name).
// Pinning the driver (RTLD_NODELETE) keeps those globals, so the blocks stay reachable; the
// suppression names the driver in case a Mesa version really leaks. Every allocation made by Kerf's
// own code is still checked.
#include <dlfcn.h>

#include <initializer_list>

extern "C" const char* __lsan_default_suppressions() { return "leak:swrast_dri.so\n"; }

namespace {

const bool kDriverPinned = [] {
    for (const char* path :
         {"/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so",
          "/usr/lib/aarch64-linux-gnu/dri/swrast_dri.so", "/usr/lib/dri/swrast_dri.so"}) {
        if (dlopen(path, RTLD_NOW | RTLD_NODELETE)) return true;
    }
    return false;
}();

}  // namespace
