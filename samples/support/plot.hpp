// SPDX-License-Identifier: Apache-2.0
// A small PNG line-plot utility on OpenCV drawing (cv::line, cv::putText, cv::imwrite), shared by
// the samples and calibration tools: a figure of stacked panels sharing the x axis, each with
// ticks, tick labels, axis labels, a title, several colored series with a legend, and shaded
// bands (a y range, e.g. a settle band) or spans (an x range, e.g. a row's exposure interval).
//
//     dynblur_plot::Figure figure(1000, "Planned move");
//     dynblur_plot::Panel& angle = figure.addPanel("angle", "theta (deg)");
//     angle.yBand(9.8, 10.2, "+-2% band").line(t, theta, "theta");
//     figure.xLabel("time (ms)");
//     figure.save("plan.png");
//
// Text is drawn with OpenCV's Hershey fonts: ASCII only (write "deg", not "°").
#ifndef DYNBLUR_SAMPLES_PLOT_HPP
#define DYNBLUR_SAMPLES_PLOT_HPP

#include <opencv2/core.hpp>

#include <deque>
#include <string>
#include <vector>

namespace dynblur_plot {

//! Color of the i-th series when none is given (a color-blind friendly palette, BGR).
cv::Scalar paletteColor(int index);

//! One plot area: its series, bands and labels. Created by Figure::addPanel.
class Panel
{
public:
    Panel(const std::string& title, const std::string& yLabel) : title_(title), yLabel_(yLabel) {}

    //! A polyline through (x[i], y[i]); NaN samples break the line. A label puts it in the legend.
    Panel& line(const std::vector<double>& x, const std::vector<double>& y, const std::string& label = "",
                cv::Scalar color = cv::Scalar(-1, -1, -1), int thickness = 2);
    //! A horizontal reference line at y, dashed.
    Panel& hLine(double y, const std::string& label = "", cv::Scalar color = cv::Scalar(110, 110, 110));
    //! A shaded band over the y range [y0, y1] across the whole width (e.g. a tolerance band).
    Panel& yBand(double y0, double y1, const std::string& label = "",
                 cv::Scalar color = cv::Scalar(120, 200, 120), double opacity = 0.25);
    //! A shaded span over the x range [x0, x1] across the whole height (e.g. an exposure interval).
    Panel& xSpan(double x0, double x1, const std::string& label = "",
                 cv::Scalar color = cv::Scalar(230, 180, 120), double opacity = 0.25);
    //! A horizontal bar over [x0, x1] at height y, `thickness` pixels (e.g. one row's exposure).
    Panel& hBar(double x0, double x1, double y, const std::string& label = "",
                cv::Scalar color = cv::Scalar(200, 120, 40), int thickness = 4);
    //! Fixes the y range instead of fitting it to the data.
    Panel& yLimits(double lo, double hi);

private:
    friend class Figure;
    struct Series
    {
        std::vector<double> x, y;
        std::string label;
        cv::Scalar color;
        int thickness;
        bool dashed;
    };
    struct Shade
    {
        double lo, hi;        // data range along the shaded axis
        bool alongX;          // span over x (true) or band over y (false)
        std::string label;
        cv::Scalar color;
        double opacity;
    };
    struct Bar
    {
        double x0, x1, y;
        std::string label;
        cv::Scalar color;
        int thickness;
    };

    void dataRange(double& xMin, double& xMax, double& yMin, double& yMax) const;
    void render(cv::Mat& canvas, const cv::Rect& area, double xMin, double xMax, bool drawXTickLabels,
                const std::string& xLabel) const;

    std::string title_, yLabel_;
    std::vector<Series> series_;
    std::vector<Shade> shades_;
    std::vector<Bar> bars_;
    bool fixedY_ = false;
    double yLo_ = 0, yHi_ = 1;
};

//! Panels stacked top to bottom, sharing one x axis (labelled on the bottom panel).
class Figure
{
public:
    //! @param width image width, pixels. @param title figure title ("" for none).
    explicit Figure(int width = 1000, const std::string& title = "", int panelHeight = 260);

    //! Adds a panel below the others; the reference stays valid for the Figure's lifetime.
    Panel& addPanel(const std::string& title = "", const std::string& yLabel = "");
    Figure& xLabel(const std::string& label);
    //! Fixes the shared x range instead of fitting it to the data.
    Figure& xLimits(double lo, double hi);

    cv::Mat render() const;
    //! Renders and writes the image (format by extension); false when writing fails.
    bool save(const std::string& filename) const;

private:
    int width_, panelHeight_;
    std::string title_, xLabel_;
    std::deque<Panel> panels_;  // deque: references handed out by addPanel stay valid
    bool fixedX_ = false;
    double xLo_ = 0, xHi_ = 1;
};

/** @brief "Nice" tick positions (1, 2, 5 × 10^k steps) covering [lo, hi], about `target` of them.
@param step receives the tick spacing. */
std::vector<double> niceTicks(double lo, double hi, int target, double* step = nullptr);

}  // namespace dynblur_plot

#endif
