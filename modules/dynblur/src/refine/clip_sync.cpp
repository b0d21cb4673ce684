// SPDX-License-Identifier: Apache-2.0
// A clip's coarse synchronisation: the clock offset, the log's axes and the readout under which the
// log's turns between frames match the image's.
#include "precomp.hpp"

#include "refine/clip_sync.hpp"

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

const double kScanStep = 1e-3;         // the offset's scan, seconds
const double kReadoutWindow = 0.03;    // the readout's scan runs this far either side of the best offset, seconds
const int kReadoutCandidates = 11;     // line-delay scales from 0.25 to 2, geometrically
const double kMinCoverage = 0.5;       // of the turns' weight, for an offset to count

//! The weighted sums of one candidate: C = Σ w·v·gᵀ, G = Σ w·|g|², V = Σ w·|v|², over covered turns.
struct Sums
{
    Matx33d cross = Matx33d::zeros();
    double gyro = 0, image = 0, weight = 0;
};

Sums accumulate(const RateIntegral& log, const std::vector<BandTurn>& turns, const std::vector<ClipFrame>& frames,
                double offset, double lineDelayScale)
{
    Sums s;
    for (const BandTurn& t : turns)
    {
        const ClipFrame &a = frames[size_t(t.frameA)], &b = frames[size_t(t.frameB)];
        const double ta = a.frameStart + t.row * a.lineDelay * lineDelayScale + 0.5 * a.exposure + offset;
        const double tb = b.frameStart + t.row * b.lineDelay * lineDelayScale + 0.5 * b.exposure + offset;
        if (!log.covers(ta) || !log.covers(tb))
            continue;
        const Vec3d g = log.turn(ta, tb);
        s.cross += t.weight * (t.turn * g.t());
        s.gyro += t.weight * g.dot(g);
        s.image += t.weight * t.turn.dot(t.turn);
        s.weight += t.weight;
    }
    return s;
}

//! The share of the image's squared turn that M·g explains with the best scale: (tr(MᵀC))² / (G·V).
double explainedShare(const Sums& s, const Matx33d& M, double* scale = nullptr)
{
    double c = 0;
    for (int i = 0; i < 9; i++)
        c += M.val[i] * s.cross.val[i];
    if (scale)
        *scale = s.gyro > 0 ? c / s.gyro : 0;
    return c > 0 && s.gyro > 0 && s.image > 0 ? c * c / (s.gyro * s.image) : 0;
}

//! The best signed permutation for `s` and its share.
double bestPermutation(const Sums& s, Matx33d& M)
{
    double best = -1;
    for (const Matx33d& candidate : signedPermutations())
    {
        const double share = explainedShare(s, candidate);
        if (share > best)
            best = share, M = candidate;
    }
    return best;
}

//! The vertex of the parabola through (−1, a), (0, b), (1, c), in steps, within [−0.5, 0.5].
double vertex(double a, double b, double c)
{
    const double curvature = a - 2 * b + c;
    return curvature < 0 ? std::min(0.5, std::max(-0.5, 0.5 * (a - c) / curvature)) : 0.0;
}

}  // namespace

const std::vector<Matx33d>& signedPermutations()
{
    static const std::vector<Matx33d> all = [] {
        std::vector<Matx33d> matrices;
        const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
        for (const auto& order : orders)
            for (int signs = 0; signs < 8; signs++)
            {
                Matx33d M = Matx33d::zeros();
                for (int i = 0; i < 3; i++)
                    M(i, order[i]) = (signs >> i) & 1 ? -1.0 : 1.0;
                matrices.push_back(M);
            }
        return matrices;
    }();
    return all;
}

ClipSync synchronize(const RateIntegral& log, const std::vector<BandTurn>& turns, const std::vector<ClipFrame>& frames,
                     double maxTimeOffset, bool scanReadout)
{
    ClipSync sync;
    double total = 0;
    for (const BandTurn& t : turns)
        total += t.weight;
    const int steps = int(std::floor(maxTimeOffset / kScanStep + 1e-9));

    // The offset over the whole window, at the told readout, against every mapping of the axes.
    std::vector<double> shares;
    std::vector<Matx33d> mappings;
    for (int k = -steps; k <= steps; k++)
    {
        const Sums s = accumulate(log, turns, frames, k * kScanStep, 1.0);
        Matx33d M = Matx33d::eye();
        const double share = s.weight >= kMinCoverage * total ? bestPermutation(s, M) : 0.0;
        shares.push_back(share);
        mappings.push_back(M);
        sync.scanOffsets.push_back(k * kScanStep);
        sync.scanExplained.push_back(share);
    }
    size_t best = size_t(std::max_element(shares.begin(), shares.end()) - shares.begin());
    sync.axes = mappings[best];
    for (size_t k = 0; k < shares.size(); k++)
        if (std::abs(double(k) - double(best)) * kScanStep > kDistinctOffset)
            sync.runnerUp = std::max(sync.runnerUp, shares[k]);

    // The readout near that offset, the mapping held.
    double bestShare = -1, offset = sync.scanOffsets[best];
    const ClipFrame& first = frames.front();
    const double period = frames.size() > 1 ? (frames.back().frameStart - first.frameStart) / double(frames.size() - 1)
                                            : 0.0;
    std::vector<double> scales{1.0};
    if (scanReadout && first.lineDelay > 0)
    {
        scales.clear();
        for (int j = 0; j < kReadoutCandidates; j++)
        {
            const double scale = 0.25 * std::pow(8.0, double(j) / (kReadoutCandidates - 1));
            if (j == 0 || !(period > 0) || (first.rows - 1) * first.lineDelay * scale <= period)
                scales.push_back(scale);
        }
    }
    const int window = int(std::lround(kReadoutWindow / kScanStep));
    const double centre = offset;
    for (double scale : scales)
        for (int k = -window; k <= window; k++)
        {
            const double candidate = centre + k * kScanStep;
            const Sums s = accumulate(log, turns, frames, candidate, scale);
            const double share = s.weight >= kMinCoverage * total ? explainedShare(s, sync.axes) : 0.0;
            if (share > bestShare)
                bestShare = share, offset = candidate, sync.lineDelayScale = scale;
        }

    // A parabola through the best offset and its neighbours.
    double around[3];
    for (int k = -1; k <= 1; k++)
        around[k + 1] = explainedShare(accumulate(log, turns, frames, offset + k * kScanStep, sync.lineDelayScale),
                                       sync.axes);
    sync.timeOffset = offset + kScanStep * vertex(around[0], around[1], around[2]);
    const Sums s = accumulate(log, turns, frames, sync.timeOffset, sync.lineDelayScale);
    sync.explained = explainedShare(s, sync.axes, &sync.rateScale);
    sync.explainedAsTold = explainedShare(s, Matx33d::eye());
    sync.covered = total > 0 ? s.weight / total : 0;
    return sync;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
