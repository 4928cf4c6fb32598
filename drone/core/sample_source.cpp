#include "drone/core/sample_source.hpp"

namespace gs::inline core {

std::string to_string(SourceStatus s) {
    switch (s) {
        case SourceStatus::Sample:
            return "sample";
        case SourceStatus::NotYet:
            return "not yet";
        case SourceStatus::Paused:
            return "paused";
        case SourceStatus::End:
            return "end";
        case SourceStatus::Error:
            return "error";
    }
    return "unknown";
}

}  // namespace gs::inline core
