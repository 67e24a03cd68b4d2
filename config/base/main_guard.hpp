// kerf::guarded_main — the last line of every executable's main(): whatever escapes the program's
// body (an exception from a library, std::bad_alloc) becomes one line on stderr naming the
// program and exit code 1, never an abort with a core dump (issue 9, item 4).
//
//   int main(int argc, char** argv) {
//       return kerf::guarded_main("kerf-rt", [&] { return run(argc, argv); });
//   }
#pragma once

#include <cstdio>
#include <exception>
#include <new>

namespace kerf {

/// Exit code of a program whose body let an exception escape.
inline constexpr int kExitEscaped = 1;

/// Runs `body` (returns the exit code); an escaping exception is reported as "<program>: ..." on
/// stderr and gives kExitEscaped.
template <class Body>
int guarded_main(const char* program, Body&& body) noexcept {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "%s: out of memory\n", program);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: unexpected error: %s\n", program, e.what());
    } catch (...) {
        std::fprintf(stderr, "%s: unexpected error\n", program);
    }
    return kExitEscaped;
}

}  // namespace kerf
