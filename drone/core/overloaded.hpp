#pragma once
// The overloaded-lambdas visitor: std::visit(Overloaded{[](const A&) {...}, [](const B&) {...}},
// v). With one lambda per alternative and no generic one, a variant alternative nobody handles is a
// compile error, not a silent fall-through.

namespace gs {

template <class... Fs>
struct Overloaded : Fs... {
    using Fs::operator()...;
};
template <class... Fs>
Overloaded(Fs...) -> Overloaded<Fs...>;

}  // namespace gs
