#include "ui/gl_texture.hpp"

#include <GL/gl.h>
#include <opencv2/imgproc.hpp>

#include <cstdint>

namespace gs::ui {

GlVideoTexture::~GlVideoTexture() {
    if (tex_ != 0) glDeleteTextures(1, &tex_);
}

ImTextureID GlVideoTexture::video_texture(const VideoFrame& f) {
    if (f.bgr.empty() || f.bgr.type() != CV_8UC3) return nullptr;
    if (tex_ == 0) {
        glGenTextures(1, &tex_);
        glBindTexture(GL_TEXTURE_2D, tex_);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    // A new frame is a new index or new pixel storage (a replay seek can repeat an index).
    if (f.index != last_index_ || f.bgr.data != last_data_ || f.bgr.cols != w_ ||
        f.bgr.rows != h_) {
        cv::cvtColor(f.bgr, rgba_, cv::COLOR_BGR2RGBA);  // reuses rgba_ when the size is unchanged
        glBindTexture(GL_TEXTURE_2D, tex_);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        if (rgba_.cols != w_ || rgba_.rows != h_) {
            w_ = rgba_.cols;
            h_ = rgba_.rows;
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w_, h_, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                         rgba_.data);
        } else {
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w_, h_, GL_RGBA, GL_UNSIGNED_BYTE, rgba_.data);
        }
        last_index_ = f.index;
        last_data_ = f.bgr.data;
        ++uploads_;
    }
    return reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(tex_));
}

}  // namespace gs::ui
