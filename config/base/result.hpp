// kerf::Result<T, E> — a value or an error, shaped like C++23 std::expected (Debian 12's
// compilers ship none). Failures in Kerf are values: a function that can fail returns a Result,
// never throws across a module boundary.
//
//   Result<Mesh, LoadError> r = load_mesh(path, units);
//   if (!r) { log(r.error().message()); return; }
//   Mesh& m = *r;
#pragma once

#include <type_traits>
#include <utility>
#include <variant>

#include "config/base/check.hpp"

namespace kerf {

/// Wraps an error value so a Result can be built from it unambiguously: `return Err{e};`.
template <class E>
struct Err {
    E value;
};
template <class E>
Err(E) -> Err<E>;

template <class T, class E>
class [[nodiscard]] Result {
public:
    Result(const T& v) : v_(std::in_place_index<0>, v) {}        // NOLINT: implicit by design
    Result(T&& v) : v_(std::in_place_index<0>, std::move(v)) {}  // NOLINT
    template <class G>
    Result(Err<G> e) : v_(std::in_place_index<1>, std::move(e.value)) {}  // NOLINT

    bool has_value() const noexcept { return v_.index() == 0; }
    explicit operator bool() const noexcept { return has_value(); }

    T& value() & noexcept {
        KERF_ASSERT(has_value(), "value() of a Result holding an error");
        return *std::get_if<0>(&v_);
    }
    const T& value() const& noexcept {
        KERF_ASSERT(has_value(), "value() of a Result holding an error");
        return *std::get_if<0>(&v_);
    }
    T&& value() && noexcept {
        KERF_ASSERT(has_value(), "value() of a Result holding an error");
        return std::move(*std::get_if<0>(&v_));
    }
    T& operator*() & noexcept { return value(); }
    const T& operator*() const& noexcept { return value(); }
    T&& operator*() && noexcept { return std::move(*this).value(); }
    T* operator->() noexcept { return &value(); }
    const T* operator->() const noexcept { return &value(); }

    const E& error() const& noexcept {
        KERF_ASSERT(!has_value(), "error() of a Result holding a value");
        return *std::get_if<1>(&v_);
    }
    E&& error() && noexcept {
        KERF_ASSERT(!has_value(), "error() of a Result holding a value");
        return std::move(*std::get_if<1>(&v_));
    }

private:
    std::variant<T, E> v_;
};

/// Result of an operation that yields nothing but can fail.
template <class E>
class [[nodiscard]] Status {
public:
    Status() = default;
    template <class G>
    Status(Err<G> e) : err_(std::move(e.value)), ok_(false) {}  // NOLINT
    bool has_value() const noexcept { return ok_; }
    explicit operator bool() const noexcept { return ok_; }
    const E& error() const noexcept {
        KERF_ASSERT(!ok_, "error() of a successful Status");
        return err_;
    }

private:
    E err_{};
    bool ok_ = true;
};

}  // namespace kerf
