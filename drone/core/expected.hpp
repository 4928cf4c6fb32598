#pragma once
// A small Expected<T, E> (g++ 12 has std::expected only under -std=c++2b), with Expected<void, E>
// for operations that return nothing but may fail. Library code returns values or typed errors
// through this; it never throws across modules.
//
// Propagation: GS_TRY(expr) returns the error of `expr` from the enclosing function;
// GS_TRY_ASSIGN(decl, expr) does the same and otherwise declares `decl` from the value:
//     GS_TRY_ASSIGN(const auto text, read_text_file(path, name, limit));
//     GS_TRY(writer.flush());

#include <cassert>
#include <optional>
#include <type_traits>
#include <utility>
#include <variant>

namespace gs {
inline namespace core {

template <class E>
struct Unexpected {
    // A constructor rather than an aggregate: Clang 14 has no parenthesised aggregate
    // initialisation, and `Unexpected(error)` is how every error is returned.
    explicit Unexpected(E e) : error(std::move(e)) {}
    E error;
};

template <class E>
Unexpected(E) -> Unexpected<E>;

template <class T, class E>
class [[nodiscard]] Expected {
public:
    using value_type = T;
    using error_type = E;

    Expected(T value) : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit
    template <class G>
    requires std::is_constructible_v<E, G&&> Expected(Unexpected<G> e)
        : v_(std::in_place_index<1>, std::move(e.error)) {}  // NOLINT

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
    const E& error() const& {
        assert(!has_value());
        return std::get<1>(v_);
    }
    E&& error() && {
        assert(!has_value());
        return std::get<1>(std::move(v_));
    }

    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T&& operator*() && { return std::move(*this).value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

private:
    std::variant<T, E> v_;
};

// Success carries no value: `return {};` for success, `return Unexpected(e);` for an error.
template <class E>
class [[nodiscard]] Expected<void, E> {
public:
    using value_type = void;
    using error_type = E;

    Expected() = default;
    template <class G>
    requires std::is_constructible_v<E, G&&> Expected(Unexpected<G> e)
        : error_(std::in_place, std::move(e.error)) {}  // NOLINT

    bool has_value() const noexcept { return !error_.has_value(); }
    explicit operator bool() const noexcept { return has_value(); }
    void value() const { assert(has_value()); }

    const E& error() const& {
        assert(!has_value());
        return *error_;
    }
    E&& error() && {
        assert(!has_value());
        return std::move(*error_);
    }

private:
    std::optional<E> error_;
};

}  // namespace core
}  // namespace gs

#define GS_CONCAT_IMPL_(a, b) a##b
#define GS_CONCAT_(a, b) GS_CONCAT_IMPL_(a, b)

// Returns the error of `expr` (an Expected) from the enclosing function.
#define GS_TRY(expr)                                                    \
    do {                                                                \
        if (auto&& gs_try_result_ = (expr); !gs_try_result_)            \
            return ::gs::Unexpected(std::move(gs_try_result_).error()); \
    } while (false)

// Returns the error of `expr` from the enclosing function, else declares `decl` from its value.
#define GS_TRY_ASSIGN(decl, expr) GS_TRY_ASSIGN_IMPL_(GS_CONCAT_(gs_try_, __LINE__), decl, expr)
#define GS_TRY_ASSIGN_IMPL_(tmp, decl, expr)                   \
    auto tmp = (expr);                                         \
    if (!tmp) return ::gs::Unexpected(std::move(tmp).error()); \
    decl = std::move(tmp).value()
