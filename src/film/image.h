// RGB float images and their files. Every image read or written goes through OpenImageIO;
// writes go to a temporary file that is renamed into place, so a failed render leaves nothing.
#pragma once

#include <string>
#include <vector>

#include "core/assert.h"
#include "core/color.h"
#include "core/error.h"

namespace ml {

struct Image {
    int width = 0, height = 0;
    std::vector<RGB> pixels;  // row-major, top row first
    // True when the file held 8-bit (or other low-precision integer) values, which are usually
    // sRGB-encoded; the values here are as stored, scaled to [0, 1], not linearised.
    bool low_dynamic_range = false;
    int channels = 3;  // the file's channels (read_image; a grey file's 1 comes back as RGB)
    // The data window's place in the display window (OpenImageIO's ImageSpec x, y, full_width,
    // full_height): a cropped render (Film "cropwindow"/"pixelbounds") holds only the crop's
    // pixels, at (x, y) of an image full_width x full_height. Full sizes of 0 mean the image is
    // its own display window.
    int x = 0, y = 0, full_width = 0, full_height = 0;
    bool cropped() const {
        return x != 0 || y != 0 || (full_width && full_width != width) ||
               (full_height && full_height != height);
    }

    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(size_t(w) * h) {}
    RGB& at(int x, int y) {
        ML_ASSERT(x >= 0 && y >= 0 && x < width && y < height, "pixel outside the image");
        return pixels[size_t(y) * width + x];
    }
    const RGB& at(int x, int y) const {
        ML_ASSERT(x >= 0 && y >= 0 && x < width && y < height, "pixel outside the image");
        return pixels[size_t(y) * width + x];
    }
};

// Reads any format OpenImageIO knows (grey images come back as equal RGB); throws InputError
// at `loc` when the file is missing or unreadable.
Image read_image(const std::string& path, const FileLoc& loc = {});

// Writes by extension: .exr (half float), .pfm (float), .png/.jpg (tone-mapped: clamped, sRGB).
// Throws ml::Error on failure; a failed write leaves no file behind.
void write_image(const std::string& path, const Image& image);

}  // namespace ml
