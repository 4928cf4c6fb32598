#include "drone/dataset/raw_replay.hpp"

#include "drone/dataset/align.hpp"
#include "drone/dataset/csv.hpp"
#include "drone/dataset/raw.hpp"

#include <cmath>
#include <fstream>

namespace gs::dataset {

namespace {

// A cut last line (no newline) that does not parse: left out with a warning (docs/dataset.md 1.1),
// as navdata.csv's is. False when row `r` is not such a line (the problem is then an error).
bool cut_last_row(const csv::Table& t, std::size_t r, const FileError& e,
                  std::vector<std::string>* warnings) {
    if (r + 1 != t.rows() || !t.last_row_unterminated()) return false;
    if (warnings)
        warnings->push_back(to_string(e) +
                            " (incomplete last line, no newline: ignored, the recording was cut "
                            "short)");
    return true;
}

// A raw/ CSV with `columns`, or nullopt when the file ends inside its header line (a recording
// stopped before its first flush was whole): read as holding no rows, with a warning.
Expected<std::optional<csv::Table>, FileError> raw_csv(std::string text, const std::string& name,
                                                       const std::vector<const char*>& columns,
                                                       std::vector<std::string>* warnings) {
    const bool one_line = text.find('\n') == std::string::npos;
    auto t = csv::Table::parse(std::move(text), name, true);
    bool complete = t.has_value();
    for (const char* c : columns) complete = complete && t->column(c).has_value();
    if (!complete && one_line) {
        if (warnings)
            warnings->push_back(name +
                                ": incomplete header line (no newline) ignored, read as no rows: "
                                "the recording was cut short");
        return std::optional<csv::Table>();
    }
    if (!t) return Unexpected(t.error());
    if (!complete) {
        std::string names;
        for (const char* c : columns) names += (names.empty() ? "" : ",") + std::string(c);
        return Unexpected(
            FileError{FileErrorCode::Missing, name, 1, 0, "expected the columns " + names});
    }
    if (warnings && !t->cut_tail_warning().empty()) warnings->push_back(t->cut_tail_warning());
    return std::optional<csv::Table>(std::move(*t));
}

}  // namespace

Expected<std::vector<VideoConnection>, FileError> parse_video_connections(
    std::string text, std::vector<std::string>* warnings) {
    GS_TRY_ASSIGN(auto table, raw_csv(std::move(text), "raw/video_connections.csv",
                                      {"offset", "t_us"}, warnings));
    std::vector<VideoConnection> out;
    if (!table) return out;
    const csv::Table& t = *table;
    const std::size_t oc = *t.column("offset"), tc = *t.column("t_us");
    for (std::size_t r = 0; r < t.rows(); ++r) {
        auto o = t.integer(r, oc);
        auto tu = t.integer(r, tc);
        if (!o || !tu) {
            const FileError e = !o ? o.error() : tu.error();
            if (cut_last_row(t, r, e, warnings)) break;
            return Unexpected(e);
        }
        if (*o < 0 || (!out.empty() && static_cast<std::uint64_t>(*o) < out.back().offset))
            return Unexpected(t.error_at(r, oc, "offsets must not decrease"));
        out.push_back({static_cast<std::uint64_t>(*o), *tu});
    }
    return out;
}

Expected<std::vector<RecordedCapture>, FileError> parse_capture_times(
    std::string text, std::vector<std::string>* warnings) {
    GS_TRY_ASSIGN(auto table, raw_csv(std::move(text), "raw/capture_times.csv",
                                      {"frame_number", "timestamp_ms", "t_us"}, warnings));
    std::vector<RecordedCapture> out;
    if (!table) return out;
    const csv::Table& t = *table;
    const std::size_t fc = *t.column("frame_number"), sc = *t.column("timestamp_ms"),
                      tc = *t.column("t_us");
    for (std::size_t r = 0; r < t.rows(); ++r) {
        // Only this recorder writes the file, every line with its newline: a last line without
        // one was cut, even where what is left parses (a time cut to its first digits would).
        if (r + 1 == t.rows() && t.last_row_unterminated()) {
            if (warnings)
                warnings->push_back(t.file() + ":" + std::to_string(t.line_of(r)) +
                                    ": incomplete last line (no newline) ignored: the recording "
                                    "was cut short");
            break;
        }
        auto f = t.u32(r, fc, false, false);
        auto s = t.u32(r, sc, false, false);
        auto tu = t.integer(r, tc);
        if (!f) return Unexpected(f.error());
        if (!s) return Unexpected(s.error());
        if (!tu) return Unexpected(tu.error());
        if (!*f || !*s) return Unexpected(t.error_at(r, !*f ? fc : sc, "empty field"));
        if (*tu < -(std::int64_t{1} << 50) || *tu > (std::int64_t{1} << 50))
            return Unexpected(t.error_at(r, tc, "time out of range"));
        out.push_back({**f, **s, *tu * 1000});
    }
    return out;
}

namespace {

// An optional CSV of raw/ (docs/dataset.md 1.1): nothing when the file does not exist, else its
// text (at most `limit` bytes) parsed by `parse`, or the first problem with either.
template <class Value>
Expected<std::optional<Value>, FileError> read_optional_raw(
    const std::filesystem::path& raw_dir, const char* name, std::size_t limit,
    Expected<Value, FileError> (*parse)(std::string, std::vector<std::string>*),
    std::vector<std::string>* warnings) {
    std::error_code ec;
    if (!std::filesystem::exists(raw_dir / name, ec)) return std::optional<Value>();
    GS_TRY_ASSIGN(auto path, raw_file_path(raw_dir, name));
    GS_TRY_ASSIGN(auto text, read_text_file(path, std::string("raw/") + name, limit));
    GS_TRY_ASSIGN(auto value, parse(std::move(text), warnings));
    return std::optional<Value>(std::move(value));
}

}  // namespace

Expected<std::optional<std::vector<RecordedCapture>>, FileError> read_capture_times(
    const std::filesystem::path& raw_dir, std::vector<std::string>* warnings) {
    return read_optional_raw(raw_dir, "capture_times.csv", 256u << 20, parse_capture_times,
                             warnings);
}

std::map<std::uint32_t, std::int64_t> frames_of_pave_numbers(
    const std::vector<FrameRow>& frames, const std::vector<RecordedCapture>& captures) {
    const auto us = [](TimeNs t) { return std::llround(static_cast<double>(t) * 1e-3); };
    std::map<long long, std::int64_t> frame_of_us;
    for (const FrameRow& f : frames) frame_of_us[us(f.nav.t_ns)] = f.frame;
    std::map<std::uint32_t, std::int64_t> out;
    for (const RecordedCapture& c : captures)
        if (const auto it = frame_of_us.find(us(c.t_ns)); it != frame_of_us.end())
            out[c.frame_number] = it->second;
    return out;
}

Expected<std::vector<FrameRow>, FileError> replay_raw(const std::filesystem::path& raw_dir,
                                                      RawReplayDecoders& dec,
                                                      std::vector<std::string>* warnings,
                                                      TimeNs max_nav_wait_ns) {
    GS_TRY_ASSIGN(auto nav, read_navdata_bin(raw_dir, warnings));
    std::vector<RawChunk> chunks;
    std::ifstream pave;
    std::uint64_t pave_size = 0;
    bool video_cut = false;  // raw/video_chunks.bin or raw/video.pave cut short (and said so)
    std::error_code ec;
    if (std::filesystem::exists(raw_dir / "video_chunks.bin", ec)) {
        const std::size_t warned = warnings ? warnings->size() : 0;
        GS_TRY_ASSIGN(auto c, read_video_chunks(raw_dir, warnings));
        video_cut = warnings && warnings->size() > warned;
        chunks = std::move(c);
        GS_TRY_ASSIGN(auto pave_path, raw_file_path(raw_dir, "video.pave"));
        pave.open(pave_path, std::ios::binary);
        if (!pave)
            return Unexpected(
                FileError{FileErrorCode::Missing, "raw/video.pave", 0, 0, "file not found"});
        std::error_code size_ec;
        pave_size = std::filesystem::file_size(pave_path, size_ec);
        if (size_ec) pave_size = 0;
    }
    // Connection boundaries and recorded capture times (docs/dataset.md 1.1; both optional).
    GS_TRY_ASSIGN(auto recorded_connections,
                  read_optional_raw(raw_dir, "video_connections.csv", 64u << 20,
                                    parse_video_connections, warnings));
    const std::vector<VideoConnection> connections =
        std::move(recorded_connections).value_or(std::vector<VideoConnection>());
    if (dec.capture_times) {
        auto c = read_capture_times(raw_dir, warnings);
        if (!c) return Unexpected(c.error());
        if (*c) dec.capture_times(std::move(**c));
    }
    std::size_t next_connection = 0;
    std::uint64_t pave_offset = 0;  // of the next chunk in raw/video.pave

    NavAligner aligner(max_nav_wait_ns);
    std::vector<FrameRow> rows;
    std::vector<TimeNs> captured;
    std::vector<std::uint8_t> buf;
    TimeNs latest = 0, last_frame = 0;
    auto settle = [&] {
        std::int64_t index = 0;
        NavState s;
        while (aligner.pop_ready(latest, index, s)) rows.push_back(FrameRow{index, s, {}});
    };
    std::size_t ni = 0, ci = 0;
    const auto& recs = nav.records;
    while (ni < recs.size() || ci < chunks.size()) {
        // Receive-time order; on a tie the navdata goes first (it was received first on the wire
        // more often than not; the recorder's order on ties is not recorded).
        const bool take_nav =
            ci >= chunks.size() || (ni < recs.size() && recs[ni].t_us <= chunks[ci].t_us);
        if (take_nav) {
            const TimeNs t = recs[ni].t_us * 1000;
            latest = std::max(latest, t);
            if (auto s = dec.navdata ? dec.navdata(recs[ni].payload, t) : std::nullopt) {
                s->t_ns = t;
                aligner.push_nav(*s);
            }
            ++ni;
        } else {
            const RawChunk& c = chunks[ci++];
            const TimeNs t = c.t_us * 1000;
            latest = std::max(latest, t);
            buf.resize(c.length);
            pave.read(reinterpret_cast<char*>(buf.data()), c.length);
            if (const auto got = static_cast<std::size_t>(pave.gcount()); got != c.length) {
                // Cut short (docs/dataset.md 1.1): the video ends here; the navdata goes on.
                if (warnings)
                    warnings->push_back(
                        "raw/video.pave: ends inside chunk " + std::to_string(ci - 1) + " (" +
                        std::to_string(got) + " of its " + std::to_string(c.length) +
                        " bytes at byte " + std::to_string(pave_offset) + "); it and the " +
                        std::to_string(chunks.size() - ci) +
                        " chunks after it in raw/video_chunks.bin ignored: the recording was cut "
                        "short");
                ci = chunks.size();
                video_cut = true;
                continue;
            }
            captured.clear();
            // Connections that begin inside this chunk (normally at its first byte): the bytes
            // before and after the boundary go to different connections, never joined.
            std::size_t fed = 0;
            while (next_connection < connections.size() &&
                   connections[next_connection].offset < pave_offset + c.length) {
                const VideoConnection& vc = connections[next_connection++];
                if (vc.offset == 0 && next_connection == 1) continue;  // the first one: implied
                const std::size_t cut = static_cast<std::size_t>(
                    std::max<std::uint64_t>(vc.offset, pave_offset) - pave_offset);
                if (dec.video && cut > fed)
                    dec.video(std::span(buf).subspan(fed, cut - fed), t, captured);
                fed = std::max(fed, cut);
                if (dec.begin_connection) dec.begin_connection(vc.t_us * 1000);
            }
            pave_offset += c.length;
            if (dec.video && fed < buf.size()) dec.video(std::span(buf).subspan(fed), t, captured);
            for (TimeNs cap : captured) {
                cap = cap >= 0 ? cap / 1000 * 1000 : -((-cap + 999) / 1000 * 1000);  // whole us
                // As the writer does: frames.csv times strictly increase (1 us apart at least).
                if (!(rows.empty() && aligner.pending() == 0) && cap <= last_frame)
                    cap = last_frame + 1000;
                last_frame = cap;
                aligner.push_frame(static_cast<std::int64_t>(rows.size() + aligner.pending()), cap);
                latest = std::max(latest, cap);
            }
        }
        settle();
    }
    // Bytes no chunk record covers (raw/video_chunks.bin stopped by a full disk or a kill before
    // video.pave, at a whole record): not replayed, as they have no receive time; said, not
    // dropped silently (a cut inside a record of either file has been said already).
    if (warnings && !video_cut && pave_size > pave_offset)
        warnings->push_back("raw/video.pave: the " + std::to_string(pave_size - pave_offset) +
                            " bytes after byte " + std::to_string(pave_offset) +
                            " have no record in raw/video_chunks.bin (no receive time) and were "
                            "not replayed: the recording was cut short");
    aligner.finish();
    settle();
    return rows;
}

}  // namespace gs::dataset
