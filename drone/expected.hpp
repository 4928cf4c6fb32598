#pragma once
// A small Expected<T, E>: g++ 12 has std::expected only under -std=c++2b.
// Library code returns values or typed errors through this; it never throws across modules.

#include <cassert>
#include <utility>
#include <variant>

namespace gs {

// A constructor, not an aggregate: Unexpected(e) is then valid C++20 for Clang 14 too (it does
// not implement parenthesised aggregate initialisation).
template <class E>
struct Unexpected {
    explicit Unexpected(E e) : error(std::move(e)) {}
    E error;
};

template <class E>
Unexpected(E) -> Unexpected<E>;

template <class T, class E>
class [[nodiscard]] Expected {
public:
    Expected(T value)
        : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit by design
    Expected(Unexpected<E> e) : v_(std::in_place_index<1>, std::move(e.error)) {}  // NOLINT

    bool has_value() const noexcept { return v_.index() == 0; }
    explicit operator bool() const noexcept { return has_value(); }

    T& value() & {
        assert(has_value());
        return std::get<0>(v_);
    }
    const T& value() const& {
        assert(has_value());
        return std::get<0>(v_);
    }
    T&& value() && {
        assert(has_value());
        return std::get<0>(std::move(v_));
    }
    const E& error() const {
        assert(!has_value());
        return std::get<1>(v_);
    }

    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

private:
    std::variant<T, E> v_;
};

}  // namespace gs
