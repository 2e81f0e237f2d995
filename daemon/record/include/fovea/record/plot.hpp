// A tiny raster plotter for the report: axes with 1-2-5 ticks, lines, points, bars, shaded
// spans and text (stb_easy_font), saved as PNG (stb_image_write). One thread per Plot.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fovea/result.hpp"

namespace fovea::record {

struct Rgb {
    uint8_t r = 0, g = 0, b = 0;
};

class Canvas {
public:
    Canvas(int width, int height, Rgb background = {255, 255, 255});
    int width() const { return w_; }
    int height() const { return h_; }
    void pixel(int x, int y, Rgb c);
    void rect(int x0, int y0, int x1, int y1, Rgb c);  // filled, inclusive
    void line(double x0, double y0, double x1, double y1, Rgb c, int thickness = 1);
    void dot(double x, double y, int radius, Rgb c);
    // Text with its top-left at (x, y); scale 1 is ~7 px high. Returns the width in pixels.
    int text(int x, int y, const std::string& s, Rgb c, int scale = 1);
    static int text_width(const std::string& s, int scale = 1);
    Result<void> save_png(const std::string& path) const;

private:
    int w_, h_;
    std::vector<uint8_t> px_;
};

class Plot {
public:
    Plot(int width, int height, std::string title, std::string xlabel, std::string ylabel);
    void set_x(double lo, double hi, bool log = false);
    void set_y(double lo, double hi, bool log = false);
    void line(const std::vector<double>& xs, const std::vector<double>& ys, Rgb c,
              int thickness = 1);
    void points(const std::vector<double>& xs, const std::vector<double>& ys, Rgb c,
                int radius = 2);
    void bars(const std::vector<double>& x_lo, const std::vector<double>& x_hi,
              const std::vector<double>& ys, Rgb c);
    void xspan(double x0, double x1, Rgb c);  // full-height shaded band
    void vline(double x, Rgb c, const std::string& label = {});
    void legend(const std::string& label, Rgb c);
    // Draws axes, ticks, labels and the legend over the data; call last.
    Canvas& finish();

    double px(double x) const;
    double py(double y) const;

private:
    Canvas canvas_;
    std::string title_, xlabel_, ylabel_;
    double x0_ = 0, x1_ = 1, y0_ = 0, y1_ = 1;
    bool xlog_ = false, ylog_ = false;
    int left_ = 70, right_ = 20, top_ = 50, bottom_ = 46;  // top: title, legend, y label rows
    std::vector<std::pair<std::string, Rgb>> legend_;
    int vlines_ = 0;
};

// 1-2-5 tick values covering [lo, hi] (about `target` of them).
std::vector<double> nice_ticks(double lo, double hi, int target = 6);

}  // namespace fovea::record
