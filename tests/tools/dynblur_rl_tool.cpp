// SPDX-License-Identifier: Apache-2.0
// Runs cv::dynblur::richardsonLucy on raw float32 files, so tests/python/test_rl_skimage.py can
// compare it with scikit-image's richardson_lucy on exactly the same input.
//
//   dynblur_rl_tool IMAGE ROWS COLS PSF KROWS KCOLS ITERATIONS OUT [START]
//
// IMAGE, PSF: raw little-endian float32, row-major. OUT: same format, ROWS×COLS. The run uses
// RL_BOUNDARY_ZERO without acceleration, damping or TV, and starts from the constant START
// (default 0.5, as scikit-image does).
#include <opencv2/dynblur.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>

namespace {

cv::Mat readRaw(const char* path, int rows, int cols)
{
    cv::Mat m(rows, cols, CV_32F);
    std::ifstream in(path, std::ios::binary);
    in.read(reinterpret_cast<char*>(m.data), std::streamsize(m.total() * sizeof(float)));
    if (!in)
        throw std::runtime_error(std::string("cannot read ") + std::to_string(m.total()) + " floats from " + path);
    return m;
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc != 9 && argc != 10)
    {
        std::cerr << "usage: " << argv[0] << " IMAGE ROWS COLS PSF KROWS KCOLS ITERATIONS OUT [START]\n";
        return 2;
    }
    try
    {
        const cv::Mat image = readRaw(argv[1], std::atoi(argv[2]), std::atoi(argv[3]));
        const cv::Mat psf = readRaw(argv[4], std::atoi(argv[5]), std::atoi(argv[6]));
        cv::dynblur::RLParams params;
        params.iterations = std::atoi(argv[7]);
        params.boundary = cv::dynblur::RL_BOUNDARY_ZERO;
        params.accelerate = false;
        params.damping = 0;
        params.tvWeight = 0;
        params.tolerance = 0;
        const double start = argc == 10 ? std::atof(argv[9]) : 0.5;
        cv::Mat latent;
        cv::dynblur::richardsonLucy(image, psf, latent, params, cv::Mat(image.size(), CV_32F, cv::Scalar(start)));
        std::ofstream out(argv[8], std::ios::binary);
        out.write(reinterpret_cast<const char*>(latent.data), std::streamsize(latent.total() * sizeof(float)));
        return out ? 0 : 1;
    }
    catch (const std::exception& e)
    {
        std::cerr << "dynblur_rl_tool: " << e.what() << "\n";
        return 1;
    }
}
