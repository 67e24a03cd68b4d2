// Linked into every executable and test that makes an EGL context, in sanitizer builds only
// (kerf_pin_mesa_for_sanitizers() in display/egl/CMakeLists.txt): Mesa's llvmpipe driver
// (swrast_dri.so, loaded by EGL) keeps two 56-byte blocks per context that has drawn referenced
// from its own globals, and is unloaded by eglTerminate(), so LeakSanitizer then sees them
// unreferenced and reports them from "<unknown module>" (nothing can suppress that by name).
// Pinning the driver (RTLD_NODELETE) keeps those globals, so the blocks stay reachable; the
// suppression names the driver in case a Mesa version really leaks. Every allocation made by Kerf's
// own code is still checked.
//
// The driver's thread-local storage is also why LeakSanitizer's tracer sometimes crashed at exit
// ("Tracer caught signal 11", exit 134, no leak reported; seen once in CI, in `kerf demo`): up to
// LLVM 16 / GCC 13 the runtime's __tls_get_addr interceptor takes a dynamic TLS block that starts
// 16 bytes into a page for a pre-2.25 glibc header and reads the two words before it as a block's
// address and size. A malloc'd block lands there by chance, hence a flake. Turning the interceptor
// off loses nothing on glibc >= 2.25: the blocks are malloc'd and reachable from the thread's DTV,
// so the leak check still scans them. An ASAN_OPTIONS in the environment still overrides it.
#include <dlfcn.h>

#include <initializer_list>

extern "C" const char* __lsan_default_suppressions() { return "leak:swrast_dri.so\n"; }
extern "C" const char* __asan_default_options() { return "intercept_tls_get_addr=0"; }

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
