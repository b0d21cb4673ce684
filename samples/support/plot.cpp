// SPDX-License-Identifier: Apache-2.0
#include "plot.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynblur_plot {

namespace {

const int kFont = cv::FONT_HERSHEY_SIMPLEX;
const double kTickFontScale = 0.45;
const double kLabelFontScale = 0.5;
const double kTitleFontScale = 0.65;
const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kGrid(228, 228, 228);

// Pixel margins around a panel's plot rectangle: room for tick labels, the y label and title.
const int kLeftMargin = 84, kRightMargin = 24, kTopMargin = 30, kBottomMargin = 26, kXLabelHeight = 26;

bool isUnset(const cv::Scalar& color) { return color[0] < 0; }

std::string tickLabel(double value, double step)
{
    const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
    if (std::abs(value) < 0.5 * step * 1e-6)
        value = 0;  // no "-0"
    return cv::format("%.*f", decimals, value);
}

void drawText(cv::Mat& canvas, const std::string& text, cv::Point origin, double scale, int thickness = 1,
              cv::Scalar color = kInk)
{
    cv::putText(canvas, text, origin, kFont, scale, color, thickness, cv::LINE_AA);
}

cv::Size textSize(const std::string& text, double scale, int thickness = 1)
{
    int baseline = 0;
    return cv::getTextSize(text, kFont, scale, thickness, &baseline);
}

//! Blends a filled rectangle into the image (clipped to it).
void shadeRect(cv::Mat& image, cv::Rect rect, cv::Scalar color, double opacity)
{
    rect &= cv::Rect(0, 0, image.cols, image.rows);
    if (rect.empty())
        return;
    cv::Mat roi = image(rect);
    cv::Mat fill(roi.size(), roi.type(), color);
    cv::addWeighted(fill, opacity, roi, 1 - opacity, 0, roi);
}

void dashedLine(cv::Mat& image, cv::Point a, cv::Point b, cv::Scalar color, int thickness)
{
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    const int dash = 8;
    for (double s = 0; s < length; s += 2 * dash)
    {
        const double e = std::min(length, s + dash);
        const cv::Point p(cvRound(a.x + (b.x - a.x) * s / length), cvRound(a.y + (b.y - a.y) * s / length));
        const cv::Point q(cvRound(a.x + (b.x - a.x) * e / length), cvRound(a.y + (b.y - a.y) * e / length));
        cv::line(image, p, q, color, thickness, cv::LINE_AA);
    }
}

}  // namespace

cv::Scalar paletteColor(int index)
{
    // Okabe–Ito colors, BGR.
    static const cv::Scalar palette[] = {{178, 114, 0}, {0, 94, 213}, {115, 158, 0}, {167, 121, 204},
                                         {0, 159, 230}, {233, 180, 86}, {66, 228, 240}, {0, 0, 0}};
    const int count = static_cast<int>(sizeof(palette) / sizeof(palette[0]));
    return palette[((index % count) + count) % count];
}

std::vector<double> niceTicks(double lo, double hi, int target, double* step)
{
    std::vector<double> ticks;
    if (!(hi > lo) || target < 1)
        return ticks;
    const double rough = (hi - lo) / target;
    const double magnitude = std::pow(10.0, std::floor(std::log10(rough)));
    double spacing = magnitude;
    for (double factor : {1.0, 2.0, 5.0, 10.0})
        if (factor * magnitude >= rough * 0.999)
        {
            spacing = factor * magnitude;
            break;
        }
    for (double v = std::ceil(lo / spacing - 1e-9) * spacing; v <= hi + 1e-9 * spacing; v += spacing)
        ticks.push_back(v);
    if (step)
        *step = spacing;
    return ticks;
}

// ---------------------------------------------------------------------------------------------
// Panel

Panel& Panel::line(const std::vector<double>& x, const std::vector<double>& y, const std::string& label,
                   cv::Scalar color, int thickness)
{
    CV_Assert(x.size() == y.size());
    if (isUnset(color))
        color = paletteColor(static_cast<int>(series_.size()));
    series_.push_back({x, y, label, color, thickness, false});
    return *this;
}

Panel& Panel::hLine(double y, const std::string& label, cv::Scalar color)
{
    // Stored as a series without x extent; render() stretches it across the panel.
    series_.push_back({{}, {y}, label, color, 1, true});
    return *this;
}

Panel& Panel::yBand(double y0, double y1, const std::string& label, cv::Scalar color, double opacity)
{
    shades_.push_back({std::min(y0, y1), std::max(y0, y1), false, label, color, opacity});
    return *this;
}

Panel& Panel::xSpan(double x0, double x1, const std::string& label, cv::Scalar color, double opacity)
{
    shades_.push_back({std::min(x0, x1), std::max(x0, x1), true, label, color, opacity});
    return *this;
}

Panel& Panel::hBar(double x0, double x1, double y, const std::string& label, cv::Scalar color, int thickness)
{
    bars_.push_back({std::min(x0, x1), std::max(x0, x1), y, label, color, thickness});
    return *this;
}

Panel& Panel::yLimits(double lo, double hi)
{
    CV_Assert(hi > lo);
    fixedY_ = true;
    yLo_ = lo;
    yHi_ = hi;
    return *this;
}

void Panel::dataRange(double& xMin, double& xMax, double& yMin, double& yMax) const
{
    auto grow = [](double& lo, double& hi, double v) {
        if (std::isfinite(v))
        {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    };
    for (const Series& s : series_)
    {
        for (double v : s.x)
            grow(xMin, xMax, v);
        for (double v : s.y)
            grow(yMin, yMax, v);
    }
    for (const Shade& shade : shades_)
    {
        grow(shade.alongX ? xMin : yMin, shade.alongX ? xMax : yMax, shade.lo);
        grow(shade.alongX ? xMin : yMin, shade.alongX ? xMax : yMax, shade.hi);
    }
    for (const Bar& bar : bars_)
    {
        grow(xMin, xMax, bar.x0);
        grow(xMin, xMax, bar.x1);
        grow(yMin, yMax, bar.y);
    }
}

void Panel::render(cv::Mat& canvas, const cv::Rect& area, double xMin, double xMax, bool drawXTickLabels,
                   const std::string& xLabel) const
{
    const int bottom = kBottomMargin + (drawXTickLabels && !xLabel.empty() ? kXLabelHeight : 0);
    const cv::Rect plot(area.x + kLeftMargin, area.y + kTopMargin, area.width - kLeftMargin - kRightMargin,
                        area.height - kTopMargin - bottom);

    // y range: fixed, or the data with a 6% margin so lines do not touch the frame.
    double yMin = yLo_, yMax = yHi_;
    if (!fixedY_)
    {
        double unusedLo = std::numeric_limits<double>::infinity(), unusedHi = -unusedLo;
        yMin = std::numeric_limits<double>::infinity();
        yMax = -yMin;
        dataRange(unusedLo, unusedHi, yMin, yMax);
        if (!(yMax >= yMin))
            yMin = 0, yMax = 1;
        if (yMax - yMin < 1e-12 * std::max(1.0, std::abs(yMax)))
            yMin -= 0.5, yMax += 0.5;
        const double pad = 0.06 * (yMax - yMin);
        yMin -= pad;
        yMax += pad;
    }
    auto px = [&](double x) { return (x - xMin) / (xMax - xMin) * plot.width; };
    auto py = [&](double y) { return (yMax - y) / (yMax - yMin) * plot.height; };

    cv::Mat inner = canvas(plot);  // drawing in the sub-image clips everything to the frame
    double xStep = 1, yStep = 1;
    const std::vector<double> xTicks = niceTicks(xMin, xMax, std::max(2, plot.width / 90), &xStep);
    const std::vector<double> yTicks = niceTicks(yMin, yMax, std::max(2, plot.height / 45), &yStep);
    for (double x : xTicks)
        cv::line(inner, cv::Point(cvRound(px(x)), 0), cv::Point(cvRound(px(x)), plot.height), kGrid, 1);
    for (double y : yTicks)
        cv::line(inner, cv::Point(0, cvRound(py(y))), cv::Point(plot.width, cvRound(py(y))), kGrid, 1);

    for (const Shade& shade : shades_)
    {
        const cv::Rect rect = shade.alongX
            ? cv::Rect(cv::Point(cvRound(px(shade.lo)), 0), cv::Point(cvRound(px(shade.hi)) + 1, plot.height))
            : cv::Rect(cv::Point(0, cvRound(py(shade.hi))), cv::Point(plot.width, cvRound(py(shade.lo)) + 1));
        shadeRect(inner, rect, shade.color, shade.opacity);
    }
    for (const Bar& bar : bars_)
        cv::line(inner, cv::Point(cvRound(px(bar.x0)), cvRound(py(bar.y))),
                 cv::Point(cvRound(px(bar.x1)), cvRound(py(bar.y))), bar.color, bar.thickness, cv::LINE_8);

    // Sub-pixel polylines (shift = 4 bits) keep dense, smooth curves free of staircase artefacts.
    const int shift = 4;
    const double scale = 1 << shift;
    for (const Series& s : series_)
    {
        if (s.x.empty())
        {
            const int y = cvRound(py(s.y[0]));
            dashedLine(inner, cv::Point(0, y), cv::Point(plot.width, y), s.color, s.thickness);
            continue;
        }
        std::vector<cv::Point> run;
        auto flush = [&]() {
            if (run.size() >= 2)
                cv::polylines(inner, run, false, s.color, s.thickness, cv::LINE_AA, shift);
            run.clear();
        };
        for (size_t i = 0; i < s.x.size(); ++i)
        {
            if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]))
            {
                flush();
                continue;
            }
            // Clamp far-off points so the fixed-point coordinates cannot overflow.
            const double u = std::max(-1e4, std::min(1e4, px(s.x[i])));
            const double v = std::max(-1e4, std::min(1e4, py(s.y[i])));
            run.emplace_back(cvRound(u * scale), cvRound(v * scale));
        }
        flush();
    }

    // Frame, tick marks and tick labels.
    cv::rectangle(canvas, plot, kInk, 1);
    for (double x : xTicks)
    {
        const int u = plot.x + cvRound(px(x));
        cv::line(canvas, cv::Point(u, plot.br().y), cv::Point(u, plot.br().y + 5), kInk, 1);
        if (drawXTickLabels)
        {
            const std::string text = tickLabel(x, xStep);
            const cv::Size size = textSize(text, kTickFontScale);
            drawText(canvas, text, cv::Point(u - size.width / 2, plot.br().y + 8 + size.height), kTickFontScale);
        }
    }
    for (double y : yTicks)
    {
        const int v = plot.y + cvRound(py(y));
        cv::line(canvas, cv::Point(plot.x - 5, v), cv::Point(plot.x, v), kInk, 1);
        const std::string text = tickLabel(y, yStep);
        const cv::Size size = textSize(text, kTickFontScale);
        drawText(canvas, text, cv::Point(plot.x - 8 - size.width, v + size.height / 2), kTickFontScale);
    }

    if (!title_.empty())
    {
        const cv::Size size = textSize(title_, kLabelFontScale, 1);
        drawText(canvas, title_, cv::Point(plot.x + (plot.width - size.width) / 2, area.y + kTopMargin - 9),
                 kLabelFontScale, 1);
    }
    if (drawXTickLabels && !xLabel.empty())
    {
        const cv::Size size = textSize(xLabel, kLabelFontScale);
        drawText(canvas, xLabel, cv::Point(plot.x + (plot.width - size.width) / 2, area.br().y - 8), kLabelFontScale);
    }
    if (!yLabel_.empty())
    {
        // Rendered horizontally, then turned a quarter turn to read bottom-up.
        const cv::Size size = textSize(yLabel_, kLabelFontScale);
        cv::Mat label(size.height + 8, size.width + 4, canvas.type(), cv::Scalar::all(255));
        drawText(label, yLabel_, cv::Point(2, size.height + 2), kLabelFontScale);
        cv::rotate(label, label, cv::ROTATE_90_COUNTERCLOCKWISE);
        const int x = area.x + 6;
        const int y = plot.y + (plot.height - label.rows) / 2;
        const cv::Rect target = cv::Rect(x, y, label.cols, label.rows) & cv::Rect(0, 0, canvas.cols, canvas.rows);
        if (!target.empty())
            label(cv::Rect(0, 0, target.width, target.height)).copyTo(canvas(target));
    }

    // Legend, top right inside the frame: one row per labelled item.
    struct Entry
    {
        std::string label;
        cv::Scalar color;
        int kind;  // 0 line, 1 dashed line, 2 shaded box, 3 bar
        int thickness;
    };
    std::vector<Entry> entries;
    for (const Series& s : series_)
        if (!s.label.empty())
            entries.push_back({s.label, s.color, s.dashed ? 1 : 0, s.thickness});
    for (const Shade& shade : shades_)
        if (!shade.label.empty())
            entries.push_back({shade.label, shade.color, 2, 1});
    for (const Bar& bar : bars_)
        if (!bar.label.empty())
            entries.push_back({bar.label, bar.color, 3, bar.thickness});
    if (entries.empty())
        return;
    const int rowHeight = 18, sampleWidth = 26;
    int textWidth = 0;
    for (const Entry& e : entries)
        textWidth = std::max(textWidth, textSize(e.label, kTickFontScale).width);
    const cv::Rect box(plot.br().x - textWidth - sampleWidth - 26, plot.y + 8, textWidth + sampleWidth + 18,
                       rowHeight * static_cast<int>(entries.size()) + 8);
    shadeRect(canvas, box, cv::Scalar::all(255), 0.85);
    cv::rectangle(canvas, box, cv::Scalar(190, 190, 190), 1);
    for (size_t i = 0; i < entries.size(); ++i)
    {
        const Entry& e = entries[i];
        const int yMid = box.y + 4 + rowHeight * static_cast<int>(i) + rowHeight / 2;
        const cv::Point a(box.x + 6, yMid), b(box.x + 6 + sampleWidth, yMid);
        if (e.kind == 2)
            shadeRect(canvas, cv::Rect(a.x, yMid - 5, sampleWidth, 11), e.color, 0.5);
        else if (e.kind == 1)
            dashedLine(canvas, a, b, e.color, e.thickness);
        else
            cv::line(canvas, a, b, e.color, e.thickness, cv::LINE_AA);
        drawText(canvas, e.label, cv::Point(b.x + 6, yMid + 5), kTickFontScale);
    }
}

// ---------------------------------------------------------------------------------------------
// Figure

Figure::Figure(int width, const std::string& title, int panelHeight)
    : width_(width), panelHeight_(panelHeight), title_(title)
{
    CV_Assert(width >= 200 && panelHeight >= 100);
}

Panel& Figure::addPanel(const std::string& title, const std::string& yLabel)
{
    panels_.emplace_back(title, yLabel);
    return panels_.back();
}

Figure& Figure::xLabel(const std::string& label)
{
    xLabel_ = label;
    return *this;
}

Figure& Figure::xLimits(double lo, double hi)
{
    CV_Assert(hi > lo);
    fixedX_ = true;
    xLo_ = lo;
    xHi_ = hi;
    return *this;
}

cv::Mat Figure::render() const
{
    const int titleHeight = title_.empty() ? 0 : 34;
    const int panelCount = std::max<int>(1, static_cast<int>(panels_.size()));
    const int height = titleHeight + panelCount * panelHeight_ + (xLabel_.empty() ? 0 : kXLabelHeight);
    cv::Mat canvas(height, width_, CV_8UC3, cv::Scalar::all(255));
    if (!title_.empty())
    {
        const cv::Size size = textSize(title_, kTitleFontScale, 1);
        drawText(canvas, title_, cv::Point((width_ - size.width) / 2, 10 + size.height), kTitleFontScale, 1);
    }

    // One x range for all panels, so their time axes line up.
    double xMin = xLo_, xMax = xHi_;
    if (!fixedX_)
    {
        xMin = std::numeric_limits<double>::infinity();
        xMax = -xMin;
        for (const Panel& panel : panels_)
        {
            double unusedLo = std::numeric_limits<double>::infinity(), unusedHi = -unusedLo;
            panel.dataRange(xMin, xMax, unusedLo, unusedHi);
        }
        if (!(xMax > xMin))
            xMin = 0, xMax = 1;
    }

    int y = titleHeight;
    for (size_t i = 0; i < panels_.size(); ++i)
    {
        const bool last = i + 1 == panels_.size();
        const int h = panelHeight_ + (last && !xLabel_.empty() ? kXLabelHeight : 0);
        panels_[i].render(canvas, cv::Rect(0, y, width_, h), xMin, xMax, last, xLabel_);
        y += h;
    }
    return canvas;
}

bool Figure::save(const std::string& filename) const { return cv::imwrite(filename, render()); }

}  // namespace dynblur_plot
