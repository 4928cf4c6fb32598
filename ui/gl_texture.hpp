#pragma once
// Video frame -> OpenGL texture, reusing one texture and one RGBA conversion buffer; uploads only
// when the frame index changes (glTexSubImage2D when the size is unchanged). Needs a current GL
// context; owned by the run loop.

#include "ui/windows.hpp"

#include <opencv2/core.hpp>

#include <cstdint>

namespace gs::ui {

class GlVideoTexture final : public TextureSource {
public:
    GlVideoTexture() = default;
    ~GlVideoTexture() override;
    GlVideoTexture(const GlVideoTexture&) = delete;
    GlVideoTexture& operator=(const GlVideoTexture&) = delete;

    ImTextureID video_texture(const VideoFrame& frame) override;
    std::uint64_t uploads() const { return uploads_; }

private:
    unsigned int tex_ = 0;
    int w_ = 0, h_ = 0;
    std::int64_t last_index_ = -1;
    const void* last_data_ = nullptr;
    cv::Mat rgba_;
    std::uint64_t uploads_ = 0;
};

}  // namespace gs::ui
