// Film "cropwindow" and "pixelbounds" (pbrt-v4's film pixel bounds): pbrt-v4's rounding of a
// crop window to pixels, pixel bounds under --resolution, the crop as the data window of the
// written image (and `diff` refusing images whose windows differ), errors at their line, and
// that a crop renders what the whole image holds there, by a pixel integrator, one that splats
// and a many-light one. The comparison with pbrt-v4 is tests/test_pbrt_reference.cpp's
// (film_crop).
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "film/image.h"
#include "film/image_metrics.h"
#include "integrators/render_job.h"
#include "parser_test_helpers.h"
#include "scene/scene_desc.h"
#include "temp_dir_test.h"

using namespace ml;
using namespace ml::test;

namespace {

// A lit floor and wall seen from the front; `film` is the Film's parameters past the size.
std::string scene_text(int w, int h, const std::string& film) {
    return "LookAt 0 -3 1  0 0 0.6  0 0 1\nCamera \"perspective\" \"float fov\" [ 50 ]\n"
           "Film \"rgb\" \"integer xresolution\" [ " +
           std::to_string(w) + " ] \"integer yresolution\" [ " + std::to_string(h) + " ]" + film +
           "\nSampler \"independent\"\nPixelFilter \"gaussian\"\n"
           "Integrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
           "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
           "Translate 0 -0.5 2\nReverseOrientation\nShape \"disk\" \"float radius\" [ 0.6 ]\n"
           "AttributeEnd\n"
           "Texture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 4 ] \"float vscale\" "
           "[ 4 ] \"rgb tex1\" [ 0.8 0.8 0.8 ] \"rgb tex2\" [ 0.2 0.2 0.2 ]\n"
           "Material \"diffuse\" \"texture reflectance\" \"c\"\n"
           "Shape \"trianglemesh\" \"point3 P\" [ -2 -2 0  2 -2 0  2 2 0  -2 2 0 ] "
           "\"integer indices\" [ 0 1 2  0 2 3 ] \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n"
           "Shape \"trianglemesh\" \"point3 P\" [ -2 1 0  2 1 0  2 1 2  -2 1 2 ] "
           "\"integer indices\" [ 0 1 2  0 2 3 ] \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n";
}

Image render(const std::string& text, int spp, const std::string& integrator = "path",
             std::optional<int> w = {}, std::optional<int> h = {}) {
    RenderOptions opt;
    opt.progress = false;
    opt.spp = spp;
    opt.seed = 3;
    opt.integrator = integrator;
    opt.width = w;
    opt.height = h;
    return render_scene(parse_scene_string(text, ".", "test.pbrt"), opt).image;
}

void expect_window(const Image& img, int x, int y, int w, int h, int full_w, int full_h) {
    EXPECT_EQ(img.x, x);
    EXPECT_EQ(img.y, y);
    EXPECT_EQ(img.width, w);
    EXPECT_EQ(img.height, h);
    EXPECT_EQ(img.full_width, full_w);
    EXPECT_EQ(img.full_height, full_h);
}

// The mean of each channel over [x0, x0 + w) x [y0, y0 + h) of `img`.
RGB region_mean(const Image& img, int x0, int y0, int w, int h) {
    RGB s;
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) s += img.at(x, y);
    return s / float(w * h);
}

class FilmCrop : public TempDirTest {
protected:
    FilmCrop() : TempDirTest("crop") {}
};

}  // namespace

// pbrt-v4: the crop window's corners go to ceil(resolution * fraction), in single precision.
TEST_F(FilmCrop, CropWindowRoundsUpAsPbrtV4) {
    Image img = render(scene_text(10, 8, " \"float cropwindow\" [ 0.25 0.75 0.1 0.6 ]"), 1, "path");
    expect_window(img, 3, 1, 5, 4, 10, 8);  // x: ceil(2.5) to ceil(7.5); y: ceil(0.8) to ceil(4.8)
    // Corners in either order, clamped to [0, 1].
    img = render(scene_text(10, 8, " \"float cropwindow\" [ 1.5 0.5 -1 0.5 ]"), 1);
    expect_window(img, 5, 0, 5, 4, 10, 8);
}

// Pixel bounds are pixels of the scene's resolution; --resolution keeps their share of the
// image (rounded up as a crop window's corners are), a crop window scales as a fraction.
TEST_F(FilmCrop, PixelBoundsAndResolution) {
    const std::string bounds = " \"integer pixelbounds\" [ 2 6 1 5 ]";
    expect_window(render(scene_text(10, 8, bounds), 1), 2, 1, 4, 4, 10, 8);
    expect_window(render(scene_text(10, 8, bounds), 1, "path", 20, 16), 4, 2, 8, 8, 20, 16);
    expect_window(render(scene_text(10, 8, bounds), 1, "path", 15, 12), 3, 2, 6, 6, 15, 12);
    const std::string crop = " \"float cropwindow\" [ 0.25 0.75 0.125 0.625 ]";
    expect_window(render(scene_text(10, 8, crop), 1, "path", 20, 16), 5, 2, 10, 8, 20, 16);
    // Past the image: clamped.
    expect_window(render(scene_text(10, 8, " \"integer pixelbounds\" [ -3 4 6 20 ]"), 1), 0, 6, 4,
                  2, 10, 8);
}

TEST_F(FilmCrop, BadCropsAreErrorsAtTheirLine) {
    auto error = [&](const std::string& film, const std::string& fragment) {
        expect_input_error([&] { render(scene_text(10, 8, "\n" + film), 1); }, "test.pbrt", 4, 1,
                           fragment);
    };
    error("\"float cropwindow\" [ 0 0.5 0 ]", "needs 4 values");
    error("\"integer pixelbounds\" [ 0 1 ]", "needs 4 values");
    error("\"float cropwindow\" [ 0.5 0.5 0 1 ]", "leaves no pixel");
    error("\"integer pixelbounds\" [ 20 30 0 4 ]", "leaves no pixel");
}

// The crop is written as the data window of the whole image and read back so; images whose
// windows differ are not compared pixel for pixel.
TEST_F(FilmCrop, DataWindowInTheFileAndInDiff) {
    Image img = render(scene_text(10, 8, " \"integer pixelbounds\" [ 2 6 1 5 ]"), 1);
    write_image(path("crop.exr"), img);
    Image back = read_image(path("crop.exr"));
    expect_window(back, 2, 1, 4, 4, 10, 8);
    EXPECT_NO_THROW(compare_images(back, img));
    Image moved = back;
    moved.x = 3;
    EXPECT_THROW(compare_images(moved, img), UsageError);
    Image whole(4, 4);
    EXPECT_THROW(compare_images(whole, img), UsageError);
    EXPECT_THROW(worst_blocks(whole, img, 2, 1, 0), UsageError);
    // A whole image keeps no window in its file.
    write_image(path("whole.exr"), whole);
    EXPECT_FALSE(read_image(path("whole.exr")).cropped());
}

// A crop renders what the whole image holds there: camera samples (path) and light paths joined
// to the lens (lighttracer: the lens's importance is normalised over the crop, and splats past
// its edge are dropped). The many-light integrators are checked on a crop against pbrt-v4
// (tests/test_pbrt_reference.cpp, film_crop by lightcuts).
TEST_F(FilmCrop, CropMatchesTheWholeImageThere) {
    const std::string crop = " \"integer pixelbounds\" [ 5 21 4 16 ]";
    const std::pair<const char*, int> runs[] = {{"path", 64}, {"lighttracer", 128}};
    for (auto [integrator, spp] : runs) {
        SCOPED_TRACE(integrator);
        Image whole = render(scene_text(32, 24, ""), spp, integrator);
        Image part = render(scene_text(32, 24, crop), spp, integrator);
        expect_window(part, 5, 4, 16, 12, 32, 24);
        RGB a = region_mean(part, 0, 0, 16, 12), b = region_mean(whole, 5, 4, 16, 12);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 0.03f * b[c]) << "channel " << c;
    }
}
