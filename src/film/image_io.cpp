#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "film/image.h"

namespace ml {

namespace {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext;
}

// Debian 12's OpenImageIO 2.4 reads PFM but its pnm writer only writes 8/16-bit PNM, so the
// PFM writer is these few lines: the header, then little-endian float rows from the bottom up.
bool write_pfm(const std::string& path, int w, int h, const std::vector<float>& rgb) {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return false;
    bool ok = std::fprintf(f, "PF\n%d %d\n-1.0\n", w, h) > 0;
    for (int y = h - 1; y >= 0 && ok; --y)
        ok = std::fwrite(&rgb[size_t(y) * w * 3], sizeof(float), size_t(w) * 3, f) == size_t(w) * 3;
    return std::fclose(f) == 0 && ok;
}

}  // namespace

Image read_image(const std::string& path, const FileLoc& loc) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw_input_error(loc, "cannot read image \"{}\": no such file", path);
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string err = OIIO::geterror();
        throw_input_error(loc, "cannot read image \"{}\": {}", path,
                          err.empty() ? "unknown format" : err);
    }
    const OIIO::ImageSpec& spec = in->spec();
    int w = spec.width, h = spec.height, c = spec.nchannels;
    if (w <= 0 || h <= 0 || c <= 0 || int64_t(w) * h > (int64_t(1) << 31))
        throw_input_error(loc, "image \"{}\" has an unusable size {}x{}x{}", path, w, h, c);
    std::vector<float> data(size_t(w) * h * c);
    if (!in->read_image(0, 0, 0, c, OIIO::TypeDesc::FLOAT, data.data())) {
        std::string err = in->geterror();
        throw_input_error(loc, "cannot read image \"{}\": {}", path, err);
    }
    Image img(w, h);
    if (spec.x != 0 || spec.y != 0 || spec.full_width != w || spec.full_height != h) {
        img.x = spec.x, img.y = spec.y;
        img.full_width = spec.full_width, img.full_height = spec.full_height;
    }
    img.channels = c;
    OIIO::TypeDesc fmt = spec.format;
    img.low_dynamic_range = fmt == OIIO::TypeDesc::UINT8 || fmt == OIIO::TypeDesc::INT8 ||
                            fmt == OIIO::TypeDesc::UINT16;
    for (size_t i = 0; i < size_t(w) * h; ++i) {
        const float* px = &data[i * c];
        img.pixels[i] = c >= 3 ? RGB(px[0], px[1], px[2]) : RGB(px[0]);
    }
    for (const RGB& p : img.pixels)
        if (!p.is_finite()) throw_input_error(loc, "image \"{}\" holds non-finite values", path);
    return img;
}

void write_image(const std::string& path, const Image& image) {
    std::string ext = lower_extension(path);
    bool ldr = ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tga" || ext == ".bmp";
    bool supported =
        ldr || ext == ".exr" || ext == ".pfm" || ext == ".hdr" || ext == ".tif" || ext == ".tiff";
    if (!supported)
        throw Error("cannot write \"" + path +
                    "\": unknown image extension (use .exr, .png or .pfm)");
    // Write next to the target, then rename: the target appears whole or not at all.
    std::filesystem::path target(path);
    std::filesystem::path tmp = target;
    tmp += ".tmp-" + std::to_string(::getpid()) + ext;
    int w = image.width, h = image.height;
    OIIO::ImageSpec spec(w, h, 3,
                         ldr ? OIIO::TypeDesc::UINT8
                             : (ext == ".exr" ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT));
    if (image.cropped()) {
        spec.x = image.x, spec.y = image.y;
        spec.full_x = spec.full_y = 0;
        spec.full_width = image.full_width ? image.full_width : w;
        spec.full_height = image.full_height ? image.full_height : h;
    }
    std::vector<float> data(size_t(w) * h * 3);
    for (size_t i = 0; i < size_t(w) * h; ++i)
        for (int k = 0; k < 3; ++k) {
            float v = image.pixels[i][k];
            if (!std::isfinite(v)) v = 0;
            if (ldr) v = linear_to_srgb(std::clamp(v, 0.f, 1.f));
            data[i * 3 + k] = v;
        }
    if (ext == ".exr") spec.attribute("compression", "zip");
    bool ok;
    std::string err;
    if (ext == ".pfm") {
        ok = write_pfm(tmp.string(), w, h, data);
        err = "write failed";
    } else {
        auto out = OIIO::ImageOutput::create(tmp.string());
        ok = out && out->open(tmp.string(), spec) &&
             out->write_image(OIIO::TypeDesc::FLOAT, data.data()) && out->close();
        if (!ok) err = out ? out->geterror() : OIIO::geterror();
    }
    if (!ok) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        // The user named `path`: never show the temporary name in the message.
        for (size_t at; (at = err.find(tmp.string())) != std::string::npos;)
            err.replace(at, tmp.string().size(), path);
        throw Error("cannot write \"" + path + "\": " + err);
    }
    std::error_code ec;
    std::filesystem::rename(tmp, target, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw Error("cannot write \"" + path + "\": rename failed");
    }
}

}  // namespace ml
