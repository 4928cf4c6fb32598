#include "vision/params.hpp"

#include <charconv>
#include <cstdio>

namespace gs::vision {

const char* to_string(ParamStatus s) {
    switch (s) {
        case ParamStatus::Ok:
            return "ok";
        case ParamStatus::UnknownName:
            return "unknown parameter";
        case ParamStatus::OutOfRange:
            return "value out of range";
        case ParamStatus::NotANumber:
            return "not a number";
    }
    return "?";
}

std::string format_param_value(double v, ParamType t) {
    if (t == ParamType::Boolean) return v != 0.0 ? "1" : "0";
    if (t == ParamType::Integer) return std::to_string(static_cast<long long>(v));
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

bool parse_param_value(const std::string& s, double& v) {
    if (s == "true") {
        v = 1;
        return true;
    }
    if (s == "false") {
        v = 0;
        return true;
    }
    const char* b = s.data();
    const char* e = b + s.size();
    while (b < e && *b == ' ') ++b;
    while (e > b && e[-1] == ' ') --e;
    if (b < e && *b == '+') ++b;
    const auto r = std::from_chars(b, e, v);
    return r.ec == std::errc() && r.ptr == e && !std::isnan(v);
}

Expected<ParamOverride, std::string> parse_param_override(const std::string& kv) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) return Unexpected(std::string("expected KEY=VALUE"));
    ParamOverride o;
    o.key = kv.substr(0, eq);
    const std::string value = kv.substr(eq + 1);
    if (!parse_param_value(value, o.value)) {
        std::string why = "'";  // appended, not a + chain: GCC 12 warns falsely (-Wrestrict)
        why.append(value).append("' is not a number");
        return Unexpected(std::move(why));
    }
    return o;
}

}  // namespace gs::vision
