#pragma once
// Named, ranged, described parameters over a plain params struct, so the GUI can list and tune a
// classifier live and save presets as key=value maps. A ParamTable<P> describes the members of P
// once (name, member pointer, range, description); values are exchanged as double.

#include "drone/core/expected.hpp"

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace gs::vision {

enum class ParamType { Real, Integer, Boolean };

struct ParamInfo {
    std::string name;
    ParamType type = ParamType::Real;
    double value = 0;
    double min = 0;
    double max = 0;
    std::string description;
};

enum class ParamStatus { Ok, UnknownName, OutOfRange, NotANumber };
const char* to_string(ParamStatus s);

using ParamMap = std::map<std::string, std::string>;

// A status per rejected key; empty when everything applied.
struct ParamMapErrors {
    std::vector<std::pair<std::string, ParamStatus>> rejected;
    bool ok() const { return rejected.empty(); }
};

template <class P>
class ParamTable {
public:
    using Member = std::variant<double P::*, int P::*, bool P::*>;
    struct Entry {
        std::string name;
        Member member;
        double min;
        double max;
        std::string description;
        bool resets_state;  // changing it invalidates tracking state (sizes, windows)
    };

    ParamTable& add(std::string name, Member m, double min, double max, std::string desc,
                    bool resets_state = false) {
        entries_.push_back({std::move(name), m, min, max, std::move(desc), resets_state});
        return *this;
    }

    std::vector<ParamInfo> list(const P& p) const {
        std::vector<ParamInfo> out;
        out.reserve(entries_.size());
        for (const Entry& e : entries_) out.push_back(info(p, e));
        return out;
    }

    // On success *resets (if given) tells whether the change needs a state reset.
    [[nodiscard]] ParamStatus set(P& p, std::string_view name, double v,
                                  bool* resets = nullptr) const {
        for (const Entry& e : entries_) {
            if (e.name != name) continue;
            if (std::isnan(v)) return ParamStatus::NotANumber;
            if (v < e.min || v > e.max) return ParamStatus::OutOfRange;
            std::visit(
                [&](auto m) {
                    using T = std::remove_reference_t<decltype(p.*m)>;
                    if constexpr (std::is_same_v<T, bool>)
                        p.*m = v != 0.0;
                    else if constexpr (std::is_same_v<T, int>)
                        p.*m = static_cast<int>(std::lround(v));
                    else
                        p.*m = v;
                },
                e.member);
            if (resets) *resets = e.resets_state;
            return ParamStatus::Ok;
        }
        return ParamStatus::UnknownName;
    }

    [[nodiscard]] bool get(const P& p, std::string_view name, double& v) const {
        for (const Entry& e : entries_)
            if (e.name == name) {
                v = info(p, e).value;
                return true;
            }
        return false;
    }

    ParamMap to_map(const P& p) const;
    // Applies every valid key; unknown or invalid ones are reported, never silently dropped.
    ParamMapErrors from_map(P& p, const ParamMap& m, bool* resets = nullptr) const;

    const std::vector<Entry>& entries() const { return entries_; }

private:
    static ParamInfo info(const P& p, const Entry& e) {
        ParamInfo i;
        i.name = e.name;
        i.min = e.min;
        i.max = e.max;
        i.description = e.description;
        std::visit(
            [&](auto m) {
                using T = std::remove_cvref_t<decltype(p.*m)>;
                if constexpr (std::is_same_v<T, bool>) {
                    i.type = ParamType::Boolean;
                    i.value = (p.*m) ? 1.0 : 0.0;
                } else if constexpr (std::is_same_v<T, int>) {
                    i.type = ParamType::Integer;
                    i.value = p.*m;
                } else {
                    i.type = ParamType::Real;
                    i.value = p.*m;
                }
            },
            e.member);
        return i;
    }

    std::vector<Entry> entries_;
};

// Value <-> text for key=value maps: shortest round-tripping decimal.
std::string format_param_value(double v, ParamType t);
[[nodiscard]] bool parse_param_value(const std::string& s, double& v);

// One KEY=VALUE override from a command line (--set, --assist-set), split and its value parsed;
// the error says what is wrong with it ("expected KEY=VALUE", "'x' is not a number").
struct ParamOverride {
    std::string key;
    double value = 0;
};
[[nodiscard]] Expected<ParamOverride, std::string> parse_param_override(const std::string& kv);

// Applies KEY=VALUE overrides (the command line's `option`, e.g. "--set") to `p` through `table`,
// all or none: the error names the first bad one and why (not KEY=VALUE, not a number, unknown
// key, out of range with the range); `params_flag` is the `ardrone-gs params` flag that lists
// the keys ("--odometry", "--assist"). `p` is unchanged on error.
template <class P>
[[nodiscard]] std::optional<std::string> apply_param_overrides(const ParamTable<P>& table, P& p,
                                                               const std::vector<std::string>& set,
                                                               const std::string& option,
                                                               const std::string& params_flag) {
    P q = p;
    for (const std::string& kv : set) {
        const auto o = parse_param_override(kv);
        if (!o) return option + " " + kv + ": " + o.error();
        const ParamStatus st = table.set(q, o->key, o->value);
        if (st == ParamStatus::Ok) continue;
        std::string why = option + " " + kv + ": ";
        if (st == ParamStatus::UnknownName)
            return why + "no parameter '" + o->key + "' (ardrone-gs params " + params_flag +
                   " lists them)";
        why += to_string(st);
        for (const auto& e : table.entries())
            if (e.name == o->key)
                why += " (" + format_param_value(e.min, ParamType::Real) + ".." +
                       format_param_value(e.max, ParamType::Real) + ")";
        return why;
    }
    p = q;
    return std::nullopt;
}

template <class P>
ParamMap ParamTable<P>::to_map(const P& p) const {
    ParamMap m;
    for (const Entry& e : entries_) {
        const ParamInfo i = info(p, e);
        m[e.name] = format_param_value(i.value, i.type);
    }
    return m;
}

template <class P>
ParamMapErrors ParamTable<P>::from_map(P& p, const ParamMap& m, bool* resets) const {
    ParamMapErrors errs;
    bool any_reset = false;
    for (const auto& [k, s] : m) {
        double v = 0;
        if (!parse_param_value(s, v)) {
            errs.rejected.emplace_back(k, ParamStatus::NotANumber);
            continue;
        }
        bool r = false;
        const ParamStatus st = set(p, k, v, &r);
        if (st != ParamStatus::Ok)
            errs.rejected.emplace_back(k, st);
        else
            any_reset = any_reset || r;
    }
    if (resets) *resets = any_reset;
    return errs;
}

}  // namespace gs::vision
