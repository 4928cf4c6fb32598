#pragma once
// Fixed-capacity history for plots: a ring of (x, y) samples that overwrites the oldest once full.
// Allocated once; push never allocates.

#include <cstddef>
#include <string>
#include <vector>

namespace gs::vision {

template <class T>
class RingBuffer {
public:
    explicit RingBuffer(std::size_t capacity = 0) : data_(capacity) {}
    void push(const T& v) {
        if (data_.empty()) return;
        data_[head_] = v;
        head_ = (head_ + 1) % data_.size();
        if (size_ < data_.size()) ++size_;
    }
    void clear() { head_ = size_ = 0; }
    std::size_t size() const { return size_; }
    std::size_t capacity() const { return data_.size(); }
    bool empty() const { return size_ == 0; }
    // i = 0 is the oldest kept sample, size()-1 the newest.
    const T& operator[](std::size_t i) const {
        return data_[(head_ + data_.size() - size_ + i) % data_.size()];
    }
    const T& back() const { return (*this)[size_ - 1]; }
    // Copies the newest n (or fewer) samples, oldest first, into out; returns how many.
    std::size_t copy_last(std::size_t n, T* out) const {
        if (n > size_) n = size_;
        for (std::size_t i = 0; i < n; ++i) out[i] = (*this)[size_ - n + i];
        return n;
    }

private:
    std::vector<T> data_;
    std::size_t head_ = 0;
    std::size_t size_ = 0;
};

struct PlotPoint {
    double x = 0;  // frame index or time, as the series says
    double y = 0;
};

struct PlotSeries {
    std::string name;    // e.g. "centre.scale_raw"
    std::string x_unit;  // "frame"
    RingBuffer<PlotPoint> points;
    PlotSeries() = default;
    PlotSeries(std::string n, std::string xu, std::size_t capacity)
        : name(std::move(n)), x_unit(std::move(xu)), points(capacity) {}
};

}  // namespace gs::vision
