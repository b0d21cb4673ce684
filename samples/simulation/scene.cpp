// SPDX-License-Identifier: Apache-2.0
#include "scene.hpp"

#include <opencv2/imgproc.hpp>

namespace dynblur_samples {

cv::Mat makeScene(const cv::Size& size, unsigned seed)
{
    cv::RNG rng(seed);
    cv::Mat scene(size, CV_8UC3);
    // A smooth two-axis color gradient as the backdrop.
    for (int y = 0; y < size.height; ++y)
    {
        cv::Vec3b* row = scene.ptr<cv::Vec3b>(y);
        for (int x = 0; x < size.width; ++x)
            row[x] = cv::Vec3b(static_cast<uchar>(60 + 120 * x / size.width),
                               static_cast<uchar>(80 + 100 * y / size.height),
                               static_cast<uchar>(150 - 90 * x / size.width));
    }
    const double scale = size.width / 1280.0;
    // Random filled shapes: large edges in every direction.
    for (int i = 0; i < 90; ++i)
    {
        // One draw per declarator: the order of a call's arguments is the compiler's (GCC went right
        // to left, clang goes left to right). This is GCC's, the scene the figures were measured on.
        const int y = rng.uniform(0, size.height), x = rng.uniform(0, size.width);
        const int red = rng.uniform(20, 235), green = rng.uniform(20, 235), blue = rng.uniform(20, 235);
        const cv::Point centre(x, y);
        const cv::Scalar color(blue, green, red);
        const int radius = static_cast<int>(rng.uniform(8, 70) * scale) + 2;
        if (i % 3 == 0)
            cv::circle(scene, centre, radius, color, cv::FILLED, cv::LINE_AA);
        else if (i % 3 == 1)
            cv::rectangle(scene, cv::Rect(centre, cv::Size(radius * 2, radius)), color, cv::FILLED);
        else
            cv::ellipse(scene, centre, cv::Size(radius, radius / 2 + 1), rng.uniform(0, 180), 0, 360, color, 3,
                        cv::LINE_AA);
    }
    // Fine stripes (horizontal ones are what a vertical blur erases first) and a Siemens star.
    const int stripeTop = size.height / 8, stripeHeight = size.height / 6;
    for (int k = 0; k < 24; ++k)
    {
        const int period = 2 + k / 4;
        const int left = static_cast<int>(size.width * 0.05) + k * static_cast<int>(14 * scale);
        for (int y = stripeTop; y < stripeTop + stripeHeight; y += period)
            cv::line(scene, cv::Point(left, y), cv::Point(left + static_cast<int>(10 * scale), y),
                     cv::Scalar(15, 15, 15), 1);
    }
    const cv::Point starCentre(size.width * 3 / 4, size.height / 3);
    const int starRadius = std::min(size.width, size.height) / 7;
    for (int k = 0; k < 36; k += 2)
    {
        const double a0 = CV_2PI * k / 36, a1 = CV_2PI * (k + 1) / 36;
        std::vector<cv::Point> wedge{starCentre,
                                     starCentre + cv::Point(cvRound(starRadius * std::cos(a0)), cvRound(starRadius * std::sin(a0))),
                                     starCentre + cv::Point(cvRound(starRadius * std::cos(a1)), cvRound(starRadius * std::sin(a1)))};
        cv::fillConvexPoly(scene, wedge, cv::Scalar(250, 250, 250), cv::LINE_AA);
    }
    // Text at several sizes: the detail a person checks first.
    const char* lines[] = {"dynblur: blur predicted from the plant, not guessed", "Richardson-Lucy per sensor row",
                           "0123456789 ABCDEFGHIJKLMNOPQRSTUVWXYZ", "rolling shutter + 10 deg saccade"};
    for (int i = 0; i < 4; ++i)
    {
        const double fontScale = (0.5 + 0.35 * i) * scale;
        const cv::Point origin(static_cast<int>(size.width * 0.08), static_cast<int>(size.height * (0.45 + 0.12 * i)));
        cv::putText(scene, lines[i], origin + cv::Point(2, 2), cv::FONT_HERSHEY_SIMPLEX, fontScale, cv::Scalar(0, 0, 0),
                    std::max(1, static_cast<int>(2 * scale)), cv::LINE_AA);
        cv::putText(scene, lines[i], origin, cv::FONT_HERSHEY_SIMPLEX, fontScale, cv::Scalar(245, 245, 245),
                    std::max(1, static_cast<int>(2 * scale)), cv::LINE_AA);
    }
    // A chessboard patch: corners for detectors, equal energy in x and y.
    const int square = std::max(4, static_cast<int>(18 * scale));
    const cv::Point board(size.width * 3 / 5, size.height * 3 / 5);
    for (int r = 0; r < 8; ++r)
        for (int c = 0; c < 10; ++c)
            if ((r + c) % 2 == 0)
                cv::rectangle(scene, cv::Rect(board.x + c * square, board.y + r * square, square, square),
                              cv::Scalar(10, 10, 10), cv::FILLED);
    return scene;
}

}  // namespace dynblur_samples
