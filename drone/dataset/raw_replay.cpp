#include "drone/dataset/raw_replay.hpp"

#include "drone/dataset/align.hpp"
#include "drone/dataset/raw.hpp"

#include <fstream>

namespace gs::dataset {

Expected<std::vector<FrameRow>, FileError> replay_raw(const std::filesystem::path& raw_dir,
                                                      RawReplayDecoders& dec,
                                                      TimeNs max_nav_wait_ns) {
    GS_TRY_ASSIGN(auto nav, read_navdata_bin(raw_dir));
    std::vector<RawChunk> chunks;
    std::ifstream pave;
    std::error_code ec;
    if (std::filesystem::exists(raw_dir / "video_chunks.bin", ec)) {
        GS_TRY_ASSIGN(auto c, read_video_chunks(raw_dir));
        chunks = std::move(c);
        GS_TRY_ASSIGN(auto pave_path, raw_file_path(raw_dir, "video.pave"));
        pave.open(pave_path, std::ios::binary);
        if (!pave)
            return Unexpected(
                FileError{FileErrorCode::Missing, "raw/video.pave", 0, 0, "file not found"});
    }
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
            if (auto s = dec.navdata ? dec.navdata(recs[ni].payload) : std::nullopt) {
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
            if (static_cast<std::size_t>(pave.gcount()) != c.length) break;  // killed mid-chunk
            captured.clear();
            if (dec.video) dec.video(buf, t, captured);
            for (TimeNs cap : captured) {
                cap = std::max(cap, last_frame);
                last_frame = cap;
                aligner.push_frame(static_cast<std::int64_t>(rows.size() + aligner.pending()), cap);
                latest = std::max(latest, cap);
            }
        }
        settle();
    }
    aligner.finish();
    settle();
    return rows;
}

}  // namespace gs::dataset
