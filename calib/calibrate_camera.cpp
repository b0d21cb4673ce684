// SPDX-License-Identifier: Apache-2.0
// dynblur_calibrate_camera: camera intrinsics from chessboard images, solved with ViSP.
//
//     dynblur_calibrate_camera --board 9x6 --square 0.025 --out cam.xml '../shared/data/left*.jpg'
//
// Writes cam.xml (ViSP camera XML, read by CameraModel::load and the demo's --camera), cam.yml
// (OpenCV FileStorage: camera_matrix, distortion_coefficients) and cam_views.png (every view with
// its detected corners and residual; rejected views framed in red). Each file is written to a
// temporary name and renamed, so none is ever half-written.
#include "atomic_file.hpp"  // samples/support
#include "cli_args.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using dynblur_samples::pathStem;
using dynblur_samples::renameIntoPlace;
using dynblur_samples::temporaryPathFor;

static dynblur_samples::CliOptions calibrateCameraOptions()
{
    dynblur_samples::CliOptions options("dynblur_calibrate_camera");
    options.synopsis("[options] IMAGE|'GLOB'...")
        .description("Calibrates the camera intrinsics (px, py, u0, v0 and ViSP's radial kud/kdu) from chessboard "
                     "images: corners found with OpenCV, solved with ViSP's vpCalibration (virtual visual servoing, "
                     "per view, then all views with distortion). Views without the board, unreadable ones and outliers "
                     "(residual > FACTOR x the median view's and > 0.5 px) are reported by name and left out.")
        .description("Images: file names, or quoted globs such as '../shared/data/left*.jpg' (expanded with cv::glob). "
                     "Options take --name value or --name=value.")
        .option("board", "WxH", "9x6", "inner corners per row x per column (a board of 10x7 squares is 9x6)")
        .option("square", "METRES", "0.025", "side of one square")
        .option("out", "FILE.xml", "camera.xml",
                "ViSP camera XML to write; also writes FILE.yml (OpenCV camera_matrix, distortion_coefficients) and "
                "FILE_views.png")
        .option("name", "NAME", "Camera", "camera name in the XML")
        .option("outlier-factor", "F", "3", "residual rejection factor, > 1; 0 keeps every view")
        .flag("no-png", "do not write the views mosaic")
        .positional()
        .footer("Exit status: 0 calibrated, 1 calibration failed (e.g. fewer than 3 usable views), 2 bad usage.");
    return options;
}

static int usageError(const std::string& message)
{
    std::cerr << "error: " << message << "\n(see dynblur_calibrate_camera --help)\n";
    return 2;
}

static std::string baseName(const std::string& path)
{
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}


//! The OpenCV-convention file: K, (k1 = kud, 0, 0, 0, 0), and how it was converted.
static void writeOpenCVYaml(const std::string& path, const CameraCalibration& calib)
{
    const std::string temporary = temporaryPathFor(path);
    {
        FileStorage fs(temporary, FileStorage::WRITE);
        if (!fs.isOpened())
            CV_Error(Error::StsError, "cannot write '" + temporary + "'");
        fs.writeComment("Camera intrinsics calibrated by dynblur_calibrate_camera (ViSP vpCalibration), in OpenCV's "
                        "convention.");
        fs.writeComment("distortion_coefficients = (k1, k2, p1, p2, k3) = (kud, 0, 0, 0, 0): ViSP projects with "
                        "u = u0 + px*x*(1 + kud*r^2), which is OpenCV's model with k1 = kud alone.");
        fs.writeComment("ViSP's kdu (its separate distorted-to-undistorted term) has no OpenCV counterpart; it is "
                        "kept as visp_kdu.");
        fs << "image_width" << calib.imageSize.width << "image_height" << calib.imageSize.height;
        fs << "camera_matrix" << Mat(calib.cameraMatrix());
        fs << "distortion_coefficients" << calib.openCVDistortion();
        fs << "avg_reprojection_error" << calib.globalResidual;
        fs << "visp_kud" << calib.kud << "visp_kdu" << calib.kdu;
        fs << "views_used" << calib.usedViews() << "views_given" << static_cast<int>(calib.viewNames.size());
    }
    renameIntoPlace(temporary, path);
}

//! Every view as a thumbnail with its corners and residual; rejected views framed in red.
static void writeMosaic(const std::string& path, const std::vector<Mat>& images, const CameraCalibration& calib,
                        Size board)
{
    const int n = static_cast<int>(images.size());
    const int cols = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n)))));
    const int rows = (n + cols - 1) / cols;
    const int thumbW = 320;
    const Size ref = calib.imageSize.area() > 0 ? calib.imageSize : Size(640, 480);
    const int thumbH = thumbW * ref.height / ref.width;
    const int labelH = 40;
    Mat canvas(rows * (thumbH + labelH), cols * thumbW, CV_8UC3, Scalar(255, 255, 255));
    for (int i = 0; i < n; ++i)
    {
        const Rect cell((i % cols) * thumbW, (i / cols) * (thumbH + labelH), thumbW, thumbH + labelH);
        Mat view;
        if (!images[i].empty())
        {
            if (images[i].channels() == 1)
                cvtColor(images[i], view, COLOR_GRAY2BGR);
            else
                view = images[i].clone();
            const std::vector<Point2f>& corners = calib.imagePoints[static_cast<size_t>(i)];
            if (!corners.empty())
                drawChessboardCorners(view, board, corners, true);
            resize(view, view, Size(thumbW, thumbH), 0, 0, INTER_AREA);
            view.copyTo(canvas(Rect(cell.x, cell.y, thumbW, thumbH)));
        }
        else
            putText(canvas, "unreadable", Point(cell.x + 100, cell.y + thumbH / 2), FONT_HERSHEY_SIMPLEX, 0.7,
                    Scalar(0, 0, 200), 2, LINE_AA);
        const bool used = calib.viewUsed[static_cast<size_t>(i)] != 0;
        const Scalar color = used ? Scalar(40, 140, 40) : Scalar(0, 0, 220);
        rectangle(canvas, Rect(cell.x + 1, cell.y + 1, thumbW - 2, thumbH - 2), color, used ? 1 : 3);
        const double r = calib.viewResiduals[static_cast<size_t>(i)];
        std::string label = baseName(calib.viewNames[static_cast<size_t>(i)]);
        label += std::isnan(r) ? "  -" : format("  %.3f px", r);
        putText(canvas, label, Point(cell.x + 6, cell.y + thumbH + 17), FONT_HERSHEY_SIMPLEX, 0.5, Scalar(0, 0, 0), 1,
                LINE_AA);
        std::string status = calib.viewStatus[static_cast<size_t>(i)];
        if (status.size() > 44)
            status = status.substr(0, 41) + "...";
        putText(canvas, status, Point(cell.x + 6, cell.y + thumbH + 34), FONT_HERSHEY_SIMPLEX, 0.42, color, 1,
                LINE_AA);
    }
    const std::string temporary = temporaryPathFor(path);
    if (!imwrite(temporary, canvas))
        CV_Error(Error::StsError, "cannot write '" + temporary + "'");
    renameIntoPlace(temporary, path);
}

int main(int argc, char** argv)
{
    std::vector<std::string> inputs;
    Size board;
    double square = 0, outlierFactor = 0;
    std::string out, name;
    bool png = true;
    try
    {
        const dynblur_samples::CliOptions options = calibrateCameraOptions();
        const dynblur_samples::CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        const std::string boardText = args.str("board");
        int w = 0, h = 0;
        char tail = 0;
        if (std::sscanf(boardText.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 2 || h < 2)
            return usageError("--board '" + boardText + "' must be WxH inner corners, each >= 2 (e.g. 9x6)");
        board = Size(w, h);
        square = args.num("square");
        if (!(square > 0))
            return usageError(format("--square %g must be > 0 (metres)", square));
        outlierFactor = args.num("outlier-factor");
        if (!(outlierFactor == 0 || outlierFactor > 1))
            return usageError(format("--outlier-factor %g must be > 1 (or 0 to keep every view)", outlierFactor));
        out = args.str("out");
        name = args.str("name");
        png = !args.has("no-png");
        inputs = args.positional();
    }
    catch (const std::exception& e)
    {
        return usageError(e.what());
    }
    if (inputs.empty())
        return usageError("no images given (file names or a quoted glob such as 'left*.jpg')");

    // Expand globs (quoted so the shell left them alone); plain names are kept even when missing,
    // so the report names them.
    std::vector<String> paths;
    for (const std::string& input : inputs)
    {
        if (input.find_first_of("*?[") == std::string::npos)
        {
            paths.push_back(input);
            continue;
        }
        std::vector<String> matches;
        try
        {
            glob(input, matches, false);
        }
        catch (const cv::Exception&)
        {
        }
        if (matches.empty())
        {
            std::cerr << "error: no file matches '" << input << "'\n";
            return 2;
        }
        std::sort(matches.begin(), matches.end());
        paths.insert(paths.end(), matches.begin(), matches.end());
    }

    std::vector<Mat> images;
    for (size_t i = 0; i < paths.size(); ++i)
    {
        Mat image;
        try
        {
            image = imread(paths[i], IMREAD_COLOR);
        }
        catch (const cv::Exception&)
        {
        }
        std::printf("[%2zu/%zu] %-28s %s\n", i + 1, paths.size(), baseName(paths[i]).c_str(),
                    image.empty() ? "unreadable: skipped" : format("%dx%d", image.cols, image.rows).c_str());
        std::fflush(stdout);
        images.push_back(image);
    }
    std::printf("Detecting %dx%d inner corners and calibrating with ViSP (%.4g m squares)...\n", board.width,
                board.height, square);
    std::fflush(stdout);

    CameraCalibration calib;
    try
    {
        calib = calibrateCameraViSPImages(images, paths, board, square, outlierFactor);
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "error: " << e.err << "\n";
        return 1;
    }

    std::printf("\n%-28s %-8s %-12s %s\n", "view", "corners", "residual px", "status");
    std::vector<std::string> rejected;
    for (size_t i = 0; i < paths.size(); ++i)
    {
        const double r = calib.viewResiduals[i];
        std::printf("%-28s %-8s %-12s %s\n", baseName(paths[i]).c_str(),
                    calib.imagePoints[i].empty() ? "-" : std::to_string(calib.imagePoints[i].size()).c_str(),
                    std::isnan(r) ? "-" : format("%.3f", r).c_str(), calib.viewStatus[i].c_str());
        if (!calib.viewUsed[i])
            rejected.push_back(baseName(paths[i]) + " (" + calib.viewStatus[i] + ")");
    }
    std::printf("\nViews used: %d of %zu\n", calib.usedViews(), paths.size());
    for (const std::string& r : rejected)
        std::printf("  left out: %s\n", r.c_str());
    std::printf("Global reprojection residual: %.3f px RMS (ViSP's own figure, both distortion directions: %.3f px)\n",
                calib.globalResidual, calib.vispGlobalResidual);
    std::printf("Intrinsics: px=%.2f py=%.2f u0=%.2f v0=%.2f  kud=%.5f kdu=%.5f  (%dx%d)\n", calib.px, calib.py,
                calib.u0, calib.v0, calib.kud, calib.kdu, calib.imageSize.width, calib.imageSize.height);

    const std::string yml = pathStem(out) + ".yml";
    const std::string mosaic = pathStem(out) + "_views.png";
    try
    {
        const std::string temporary = temporaryPathFor(out);
        std::remove(temporary.c_str());
        calib.cameraModel()->save(temporary, name);
        Ptr<CameraModel> back = CameraModel::load(temporary, name);  // never leave a file that does not load
        if (std::abs(back->getFx() - calib.px) > 1e-6 * calib.px)
            CV_Error(Error::StsError, "the written camera file does not read back");
        renameIntoPlace(temporary, out);
        writeOpenCVYaml(yml, calib);
        if (png)
            writeMosaic(mosaic, images, calib, board);
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "error: " << e.err << "\n";
        return 1;
    }
    std::printf("Wrote %s (ViSP camera '%s'), %s (OpenCV)%s\n", out.c_str(), name.c_str(), yml.c_str(),
                png ? (", " + mosaic).c_str() : "");
    return 0;
}
