/*=========================================================================
 *
 *  Copyright NumFOCUS and the PointBasedDRR contributors
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#include "itkDRRPointRenderer.h"
#include "itkDRRBilinearSplat.h"
#include "itkDRRBoxKernel.h"
#include "itkDRRNearestSplat.h"
#include "itkDRRTentKernel.h"
#include "itkDRRWorkScheduler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

// Clones of the hot loop for wider vectors, picked once for the CPU at load time. Every clone gives the same bits:
// contraction into FMA is off (-ffp-contract=off) and every operation used is correctly rounded.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define PointBasedDRR_VECTOR_CLONES __attribute__((target_clones("default", "avx2", "avx512f"), flatten))
#else
#define PointBasedDRR_VECTOR_CLONES
#endif

namespace itk
{
namespace
{
constexpr uint64_t     samplesPerBatch = 512;
constexpr unsigned int maximumCorners = 4; // pixels one point can reach (bilinear splat)

/** Integer fixed-point accumulators of one worker: per pixel the sum of contributions of every stratum (pixel major:
 * the strata of a pixel share a cache line), and, with a single stratum, the sum of their squares. */
struct Accumulator
{
  std::vector<int64_t> Sum;
  std::vector<int64_t> SumOfSquares;
  uint64_t             PointsOnDetector{ 0 };
};

/** One batch, structure of arrays, so that the placement and projection loops vectorize. */
struct Batch
{
  uint64_t Voxel[samplesPerBatch];
  uint32_t I[samplesPerBatch + DRRPointSampler::CoordinateSlack];
  uint32_t J[samplesPerBatch + DRRPointSampler::CoordinateSlack];
  uint32_t K[samplesPerBatch + DRRPointSampler::CoordinateSlack];
  double   Weight[samplesPerBatch];
  uint32_t Stratum[samplesPerBatch];
  uint32_t JitterX[samplesPerBatch], JitterY[samplesPerBatch], JitterZ[samplesPerBatch];
  double   X[samplesPerBatch], Y[samplesPerBatch], Z[samplesPerBatch];
  double   Column[samplesPerBatch], Row[samplesPerBatch], Perspective[samplesPerBatch];
  int32_t  Pixel[maximumCorners * samplesPerBatch]; // per point and splat corner; -1: off the detector
  int64_t  Value[maximumCorners * samplesPerBatch]; // fixed point
  int64_t  Square[maximumCorners * samplesPerBatch];
};

/** What one worker owns: its sums and its batch (allocated once per render, not per chunk). */
struct Worker
{
  Accumulator            Sums;
  std::unique_ptr<Batch> Scratch{ new Batch };
};

/** The strata of a render. Contiguous: R runs of consecutive samples, of N / R samples each (up to one).
 * Interleaved (DRRPointSampler::InterleavesStrata()): R strata of ceil(N / R) samples each, drawn as one run in which
 * the sampler tells the stratum of every sample. */
class Strata
{
public:
  Strata(uint64_t numberOfSamples, uint64_t numberOfStrata, bool interleaved)
    : m_NumberOfStrata(numberOfStrata), m_Interleaved(interleaved && numberOfStrata > 1)
  {
    if (m_Interleaved)
    {
      m_InterleavedSize = (numberOfSamples + numberOfStrata - 1) / numberOfStrata;
      m_First = { 0, m_InterleavedSize * numberOfStrata };
      return;
    }
    for (uint64_t r = 0; r <= numberOfStrata; ++r)
    {
      m_First.push_back(static_cast<uint64_t>((static_cast<unsigned __int128>(numberOfSamples) * r) / numberOfStrata));
    }
  }
  /** Samples drawn (N, or R ceil(N / R) when interleaved). */
  uint64_t
  GetNumberOfSamples() const
  {
    return m_First.back();
  }
  uint64_t
  GetNumberOfStrata() const
  {
    return m_NumberOfStrata;
  }
  bool
  IsInterleaved() const
  {
    return m_Interleaved;
  }
  uint64_t
  Size(uint64_t stratum) const
  {
    return m_Interleaved ? m_InterleavedSize : this->RunSize(stratum);
  }
  /** Runs of consecutive samples (the strata, or the one run of interleaved strata). */
  uint64_t
  RunOfSample(uint64_t sample) const
  {
    return static_cast<uint64_t>(std::upper_bound(m_First.begin(), m_First.end(), sample) - m_First.begin()) - 1;
  }
  uint64_t
  RunFirst(uint64_t run) const
  {
    return m_First[run];
  }
  uint64_t
  RunSize(uint64_t run) const
  {
    return m_First[run + 1] - m_First[run];
  }

private:
  uint64_t              m_NumberOfStrata;
  bool                  m_Interleaved;
  uint64_t              m_InterleavedSize{ 0 };
  std::vector<uint64_t> m_First;
};

/** Largest k with count * bound * 2^k <= 2^62, so that no sum of count contributions <= bound overflows. */
int
FixedPointExponent(double count, double bound)
{
  return static_cast<int>(std::floor(62.0 - std::log2(std::max(count * bound, 1e-300))));
}

/** Renders whole chunks; one instantiation per reconstruction kernel and splat, chosen once per render. */
class ChunkRendererBase
{
public:
  virtual ~ChunkRendererBase() = default;
  virtual void
  Render(uint64_t chunk, const Strata & strata, Worker & worker) const = 0;
};

template <typename TKernel, typename TSplat>
class ChunkRenderer : public ChunkRendererBase
{
public:
  ChunkRenderer(const DRRAttenuationVolume &       volume,
                const DRRPointSampler &            sampler,
                const DRRPointProjection &         projection,
                const DRRPointRenderer::Settings & settings,
                double                             sumScale,
                double                             squareScale,
                bool                               smallFixedPoint)
    : m_Sampler(sampler)
    , m_Projection(projection)
    , m_Settings(settings)
    , m_NX(volume.GetSize()[0])
    , m_NXY(volume.GetSize()[0] * volume.GetSize()[1])
    , m_Columns(static_cast<int64_t>(projection.GetNumberOfColumns()))
    , m_Rows(static_cast<int64_t>(projection.GetNumberOfRows()))
    , m_SumScale(sumScale)
    , m_SquareScale(squareScale)
    , m_SmallFixedPoint(smallFixedPoint)
  {}

  void
  Render(uint64_t chunk, const Strata & strata, Worker & worker) const override
  {
    this->RenderChunk(chunk, strata, worker);
  }

private:
  PointBasedDRR_VECTOR_CLONES void
  RenderChunk(uint64_t chunk, const Strata & strata, Worker & worker) const
  {
    const uint64_t  end = std::min((chunk + 1) * DRRPointRenderer::SamplesPerChunk, strata.GetNumberOfSamples());
    DRRPhiloxRandom samplerStream(m_Settings.Seed, chunk, 0);
    DRRPhiloxRandom kernelStream(m_Settings.Seed, chunk, 1);
    Batch &         batch = *worker.Scratch;
    DRRPointSampler::Cursor      cursor;
    DRRPointSampler::SampleRange range;
    range.Seed = m_Settings.Seed;
    range.NumberOfStrata = strata.IsInterleaved() ? strata.GetNumberOfStrata() : 1;
    for (range.First = chunk * DRRPointRenderer::SamplesPerChunk; range.First < end; range.First += range.Count)
    {
      // A batch never straddles two runs.
      range.Stratum = strata.RunOfSample(range.First);
      range.StratumFirst = strata.RunFirst(range.Stratum);
      range.StratumSize = strata.RunSize(range.Stratum);
      range.Count =
        std::min({ samplesPerBatch, end - range.First, range.StratumFirst + range.StratumSize - range.First });
      this->DrawVoxels(samplerStream, range, cursor, batch);
      if (!strata.IsInterleaved())
      {
        std::fill(batch.Stratum, batch.Stratum + range.Count, static_cast<uint32_t>(range.Stratum));
      }
      if (!m_Sampler.ProvidesJitter())
      {
        DrawJitter(kernelStream, range.Count, batch);
      }
      PlacePoints(range.Count, batch);
      m_Projection.ProjectBatch(range.Count, batch.X, batch.Y, batch.Z, batch.Column, batch.Row, batch.Perspective);
      this->Splat(range.Count, batch, strata.GetNumberOfStrata(), worker.Sums);
    }
  }

  void
  DrawVoxels(DRRPhiloxRandom &                    stream,
             const DRRPointSampler::SampleRange & range,
             DRRPointSampler::Cursor &            cursor,
             Batch &                              batch) const
  {
    if (m_Sampler.GeneratesCoordinates())
    {
      m_Sampler.GenerateCoordinates(
        range,
        cursor,
        { batch.I, batch.J, batch.K, batch.Weight, batch.Stratum, batch.JitterX, batch.JitterY, batch.JitterZ });
      return;
    }
    m_Sampler.GenerateBatch(stream, range, batch.Voxel, batch.Weight);
    for (uint64_t s = 0; s < range.Count; ++s)
    {
      const uint64_t k = batch.Voxel[s] / m_NXY;
      const uint64_t rest = batch.Voxel[s] - k * m_NXY;
      const uint64_t j = rest / m_NX;
      batch.I[s] = static_cast<uint32_t>(rest - j * m_NX);
      batch.J[s] = static_cast<uint32_t>(j);
      batch.K[s] = static_cast<uint32_t>(k);
    }
  }

  static void
  DrawJitter(DRRPhiloxRandom & stream, uint64_t count, Batch & batch)
  {
    for (uint64_t s = 0; s < count; ++s)
    {
      const DRRPhiloxRandom::BlockType bits = stream.Next();
      batch.JitterX[s] = bits[0];
      batch.JitterY[s] = bits[1];
      batch.JitterZ[s] = bits[2];
    }
  }

  /** Continuous index of every point: its voxel centre plus the kernel's offset. */
  static void
  PlacePoints(uint64_t count, Batch & batch)
  {
    for (uint64_t s = 0; s < count; ++s)
    {
      batch.X[s] = static_cast<double>(static_cast<int32_t>(batch.I[s])) + TKernel::Offset(batch.JitterX[s]);
      batch.Y[s] = static_cast<double>(static_cast<int32_t>(batch.J[s])) + TKernel::Offset(batch.JitterY[s]);
      batch.Z[s] = static_cast<double>(static_cast<int32_t>(batch.K[s])) + TKernel::Offset(batch.JitterZ[s]);
    }
  }

  /** Adds every point to the fixed-point sums of its stratum (and to the sums of squares, with one stratum): first
   * the pixel and fixed-point value of every corner (a loop that vectorizes), then the additions. */
  void
  Splat(uint64_t count, Batch & batch, uint64_t numberOfStrata, Accumulator & sums) const
  {
    constexpr unsigned int corners = TSplat::Corners;
    static_assert(corners <= maximumCorners, "Batch holds at most maximumCorners corners per point");
    const bool    unbiased = m_Settings.Weighting == PointBasedDRREnums::PointWeighting::Unbiased;
    const bool    squares = !sums.SumOfSquares.empty();
    const double  sumScale = m_SumScale;
    const double  squareScale = m_SquareScale;
    const int32_t columns = static_cast<int32_t>(m_Columns);
    const int32_t rows = static_cast<int32_t>(m_Rows);
    const auto    round = m_SmallFixedPoint ? &RoundSmall : &RoundAny;
    for (uint64_t s = 0; s < count; ++s)
    {
      // A point that does not count has perspective weight 0 and lands off the detector.
      const double weight = unbiased ? batch.Weight[s] * batch.Perspective[s] : batch.Weight[s];
      int32_t      pixel[corners];
      double       share[corners];
      TSplat::Locate(batch.Column[s], batch.Row[s], columns, rows, pixel, share);
      for (unsigned int c = 0; c < corners; ++c)
      {
        const double contribution = weight * share[c];
        batch.Pixel[corners * s + c] = pixel[c];
        batch.Value[corners * s + c] = round(contribution * sumScale);
        batch.Square[corners * s + c] = squares ? round(contribution * contribution * squareScale) : 0;
      }
    }
    int64_t * sumOfSquares = sums.SumOfSquares.data();
    uint64_t  landed = 0;
    for (uint64_t s = 0; s < count; ++s)
    {
      int64_t * sum = sums.Sum.data() + (numberOfStrata > 1 ? batch.Stratum[s] : 0);
      bool      reached = false;
      for (unsigned int c = 0; c < corners; ++c)
      {
        const int32_t pixel = batch.Pixel[corners * s + c];
        if (pixel >= 0)
        {
          sum[pixel * numberOfStrata] += batch.Value[corners * s + c];
          if (squares)
          {
            sumOfSquares[pixel] += batch.Square[corners * s + c];
          }
          reached = true;
        }
      }
      landed += reached ? 1 : 0;
    }
    sums.PointsOnDetector += landed;
  }

  /** llrint(x), for |x| < 2^51: adding 1.5 2^52 rounds to the nearest integer (ties to even, as llrint) in the low
   * mantissa bits; this form vectorizes. */
  static int64_t
  RoundSmall(double x)
  {
    const double shifted = x + 6755399441055744.0;
    int64_t      bits;
    std::memcpy(&bits, &shifted, sizeof(bits));
    return bits - 0x4338000000000000;
  }
  static int64_t
  RoundAny(double x)
  {
    return std::llrint(x);
  }

  const DRRPointSampler &            m_Sampler;
  const DRRPointProjection &         m_Projection;
  const DRRPointRenderer::Settings & m_Settings;
  const uint64_t                     m_NX;
  const uint64_t                     m_NXY;
  const int64_t                      m_Columns;
  const int64_t                      m_Rows;
  const double                       m_SumScale;
  const double                       m_SquareScale;
  const bool                         m_SmallFixedPoint; // every fixed-point value below 2^51: RoundSmall()
};
/** The registered splats: calls visit with a value of the splat policy's type. One case per splat. */
template <typename TVisit>
auto
WithSplat(PointBasedDRREnums::Splat splat, TVisit && visit)
{
  switch (splat)
  {
    case PointBasedDRREnums::Splat::Nearest:
      return visit(DRRNearestSplat{});
    case PointBasedDRREnums::Splat::Bilinear:
      return visit(DRRBilinearSplat{});
  }
  itkGenericExceptionMacro("DRRPointRenderer: unknown splat " << splat);
}

/** The registered reconstruction kernels: calls visit with a value of the kernel policy's type. One case per kernel. */
template <typename TVisit>
auto
WithKernel(PointBasedDRREnums::ReconstructionKernel kernel, TVisit && visit)
{
  switch (kernel)
  {
    case PointBasedDRREnums::ReconstructionKernel::Box:
      return visit(DRRBoxKernel{});
    case PointBasedDRREnums::ReconstructionKernel::Tent:
      return visit(DRRTentKernel{});
  }
  itkGenericExceptionMacro("DRRPointRenderer: unknown reconstruction kernel " << kernel);
}
} // namespace

void
DRRPointRenderer::ComputeKernelSupport(const DRRAttenuationVolume & volume,
                                       KernelEnum                   kernel,
                                       std::array<double, 3> &      lower,
                                       std::array<double, 3> &      upper)
{
  const double reach = WithKernel(kernel, [](auto policy) { return decltype(policy)::Reach; });
  for (unsigned int a = 0; a < 3; ++a)
  {
    lower[a] = -reach;
    upper[a] = static_cast<double>(volume.GetSize()[a]) - 1.0 + reach;
  }
}

DRRPointRenderer::Result
DRRPointRenderer::Render(const DRRAttenuationVolume & volume,
                         DRRPointSampler &            sampler,
                         DRRPointProjection           projection,
                         const Settings &             settings,
                         MultiThreaderBase *          threader,
                         ProcessObject *              progressFilter)
{
  if (settings.NumberOfSamples == 0)
  {
    itkGenericExceptionMacro("DRRPointRenderer: the number of samples must be at least 1");
  }
  const size_t numberOfPixels =
    static_cast<size_t>(projection.GetNumberOfColumns()) * static_cast<size_t>(projection.GetNumberOfRows());
  Result result;
  result.LineIntegral.assign(numberOfPixels, 0.0);
  result.StandardError.assign(numberOfPixels, 0.0);
  result.RoomMass = sampler.GetTotalMass() * projection.GetRoomMassScale();
  if (!(result.RoomMass > 0.0))
  {
    return result; // all air: the exact answer is a zero image
  }
  // Sample only what can reach the detector (for samplers that cull).
  const double kernelReach = WithKernel(settings.Kernel, [](auto policy) { return decltype(policy)::Reach; });
  const double splatReach = WithSplat(settings.Splat, [](auto policy) { return decltype(policy)::Reach; });
  sampler.SetView(&projection, kernelReach, splatReach);
  result.SampledRoomMass = sampler.GetSampledMass() * projection.GetRoomMassScale();
  if (!(result.SampledRoomMass > 0.0))
  {
    return result; // nothing in view: the exact answer is a zero image
  }

  // Dependent points (stratified, Markov chains): independent strata, whose spread gives the standard error.
  const uint64_t requestedStrata =
    settings.NumberOfStrata > 0 ? settings.NumberOfStrata : sampler.GetPreferredNumberOfStrata();
  const bool useStrata =
    !sampler.HasIndependentSamples() && requestedStrata > 1 && settings.NumberOfSamples >= 16 * requestedStrata;
  const Strata   strata(settings.NumberOfSamples, useStrata ? requestedStrata : 1, sampler.InterleavesStrata());
  const uint64_t numberOfStrata = strata.GetNumberOfStrata();

  // Bound the contributions so the fixed-point sums cannot overflow. In perspective, the weight grows as
  // (SID / z)^2 near the source; if the volume comes that close, drop the points nearer than the depth that keeps
  // at least 20 fractional bits (the dropped part of each ray is shorter than that depth).
  const double N = static_cast<double>(strata.GetNumberOfSamples());
  double       contributionBound = sampler.GetMaximumWeight();
  if (projection.IsPerspective() && settings.Weighting == WeightingEnum::Unbiased)
  {
    std::array<double, 3> lower, upper;
    ComputeKernelSupport(volume, settings.Kernel, lower, upper);
    double nearest, farthest;
    projection.ComputeDepthRange(lower, upper, nearest, farthest);
    const double sid = projection.GetSourceToDetectorDistance();
    const double obliquity = projection.GetMaximumObliquity();
    const double largestAffordableWeight = std::ldexp(1.0, 42) / (N * sampler.GetMaximumWeight());
    const double depthCut = sid * std::sqrt(obliquity / largestAffordableWeight);
    // Only a volume whose depth range reaches into (0, depthCut) comes near the source; one wholly behind it does not.
    result.SourceNearVolume = nearest < depthCut && farthest > 0.0;
    const double minimumDepth = std::max(depthCut, nearest);
    projection.SetMinimumDepth(result.SourceNearVolume ? depthCut : 0.0);
    result.MinimumDepth = result.SourceNearVolume ? depthCut : 0.0;
    contributionBound *= (sid / minimumDepth) * (sid / minimumDepth) * obliquity;
  }
  const int    sumExponent = FixedPointExponent(N, contributionBound);
  const int    squareExponent = FixedPointExponent(N, contributionBound * contributionBound);
  const double sumScale = std::ldexp(1.0, sumExponent);
  const double squareScale = std::ldexp(1.0, squareExponent);
  // Each contribution is at most 2^62 / N in fixed point (both sums): below 2^51 from N = 2^11 on.
  const bool                               smallFixedPoint = N >= 4096.0;
  const std::unique_ptr<ChunkRendererBase> chunkRenderer = WithKernel(settings.Kernel, [&](auto kernel) {
    return WithSplat(settings.Splat, [&](auto splat) -> std::unique_ptr<ChunkRendererBase> {
      return std::make_unique<ChunkRenderer<decltype(kernel), decltype(splat)>>(
        volume, sampler, projection, settings, sumScale, squareScale, smallFixedPoint);
    });
  });

  const uint64_t      numberOfChunks = (strata.GetNumberOfSamples() + SamplesPerChunk - 1) / SamplesPerChunk;
  std::vector<Worker> workers(DRRWorkScheduler::GetNumberOfWorkers(threader, numberOfChunks));
  for (Worker & worker : workers)
  {
    worker.Sums.Sum.assign(numberOfPixels * numberOfStrata, 0);
    if (numberOfStrata == 1)
    {
      worker.Sums.SumOfSquares.assign(numberOfPixels, 0);
    }
  }
  DRRWorkScheduler::Run(
    threader,
    numberOfChunks,
    [&](unsigned int worker, uint64_t chunk) { chunkRenderer->Render(chunk, strata, workers[worker]); },
    progressFilter);

  // Integer reduction: exact, hence independent of the order and of the worker that held each chunk.
  const double        valueScale = result.SampledRoomMass / (N * projection.GetPixelArea());
  const double        inverseSumScale = std::ldexp(1.0, -sumExponent);
  const double        inverseSquareScale = std::ldexp(1.0, -squareExponent);
  std::vector<double> stratumSums(numberOfStrata);
  for (size_t p = 0; p < numberOfPixels; ++p)
  {
    double s = 0.0;
    for (uint64_t r = 0; r < numberOfStrata; ++r)
    {
      int64_t sum = 0;
      for (const Worker & worker : workers)
      {
        sum += worker.Sums.Sum[p * numberOfStrata + r];
      }
      stratumSums[r] = static_cast<double>(sum) * inverseSumScale;
      s += stratumSums[r];
    }
    result.LineIntegral[p] = valueScale * s;
    if (numberOfStrata == 1)
    {
      int64_t sumOfSquares = 0;
      for (const Worker & worker : workers)
      {
        sumOfSquares += worker.Sums.SumOfSquares[p];
      }
      const double s2 = static_cast<double>(sumOfSquares) * inverseSquareScale;
      const double variance = strata.GetNumberOfSamples() > 1 ? N / (N - 1.0) * std::max(0.0, s2 - s * s / N) : s2;
      result.StandardError[p] = valueScale * std::sqrt(variance);
    }
    else
    {
      // Each stratum is an independent estimate L_r = M / (n_r a) S_r of the same image; the variance of their
      // combination is estimated from their spread.
      double squaredDeviations = 0.0;
      for (uint64_t r = 0; r < numberOfStrata; ++r)
      {
        const double estimate = result.SampledRoomMass / (strata.Size(r) * projection.GetPixelArea()) * stratumSums[r];
        squaredDeviations += (estimate - result.LineIntegral[p]) * (estimate - result.LineIntegral[p]);
      }
      result.StandardError[p] = std::sqrt(squaredDeviations / (numberOfStrata * (numberOfStrata - 1.0)));
    }
  }
  result.NumberOfStrata = numberOfStrata;
  result.NumberOfSamples = strata.GetNumberOfSamples();
  for (const Worker & worker : workers)
  {
    result.PointsOnDetector += worker.Sums.PointsOnDetector;
  }
  return result;
}
} // namespace itk
