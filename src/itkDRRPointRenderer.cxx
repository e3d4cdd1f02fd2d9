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
#include "itkDRRPointCloud.h"
#include "itkDRRWorkScheduler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

// Clones of the hot loop for wider vectors, picked once for the CPU at load time. Every clone gives the same bits:
// contraction into FMA is off (-ffp-contract=off) and every operation used is correctly rounded. Not under
// ThreadSanitizer: the clones' resolver runs while the loader relocates the program, before TSan's runtime has
// started, and GCC instruments it (a crash at load, before main).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) &&                           \
  !defined(__SANITIZE_THREAD__)
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

/** One batch of the render of a kept cloud, in single precision (see DRRPointProjection::ProjectBatch()). Corner
 * major (corner c of point s at c * samplesPerBatch + s), so that every store of the preparation loop is contiguous. */
struct CloudBatch
{
  float   Column[samplesPerBatch], Row[samplesPerBatch], Perspective[samplesPerBatch];
  int32_t Index[maximumCorners * samplesPerBatch]; // into the sums: pixel * strata + stratum, or the trash slot
  int64_t Value[maximumCorners * samplesPerBatch]; // fixed point
  int64_t Square[maximumCorners * samplesPerBatch];
  int32_t Stratum[samplesPerBatch];
};

/** What one worker owns: its sums and its batch (allocated once per render, not per chunk; only the kind of batch
 * its render uses). */
struct Worker
{
  Accumulator                 Sums;
  std::unique_ptr<Batch>      Scratch;
  std::unique_ptr<CloudBatch> CloudScratch;
};

} // namespace

/** The workers of a render, kept for the next (see DRRPointRenderer::MakeWorkspace()). */
class DRRPointRenderer::Workspace
{
public:
  std::vector<Worker> Workers;
  bool                Cleared{ false }; // every sum of every worker is zero
};

namespace
{
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

/** Draws the points of a chunk's samples, a batch at a time: voxel (sampler), stratum, and position inside the voxel
 * (kernel), into the batch's continuous indices X, Y, Z and weights. One instantiation per reconstruction kernel. */
template <typename TKernel>
class PointDrawer
{
public:
  PointDrawer(const DRRAttenuationVolume & volume, const DRRPointSampler & sampler, uint64_t seed)
    : m_Sampler(sampler), m_NX(volume.GetSize()[0]), m_NXY(volume.GetSize()[0] * volume.GetSize()[1]), m_Seed(seed)
  {}

  /** Calls consume(first, count) after each batch of the chunk's samples is placed (first: its first sample). */
  template <typename TConsume>
  inline void
  DrawChunk(uint64_t chunk, const Strata & strata, Batch & batch, TConsume && consume) const
  {
    const uint64_t  end = std::min((chunk + 1) * DRRPointRenderer::SamplesPerChunk, strata.GetNumberOfSamples());
    DRRPhiloxRandom samplerStream(m_Seed, chunk, 0);
    DRRPhiloxRandom kernelStream(m_Seed, chunk, 1);
    DRRPointSampler::Cursor      cursor;
    DRRPointSampler::SampleRange range;
    range.Seed = m_Seed;
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
      consume(range.First, range.Count);
    }
  }

private:
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

  const DRRPointSampler & m_Sampler;
  const uint64_t          m_NX;
  const uint64_t          m_NXY;
  const uint64_t          m_Seed;
};

/** Fixed-point scales of a render (see FixedPointExponent()). */
struct FixedPoint
{
  int  SumExponent{ 0 };
  int  SquareExponent{ 0 };
  bool Small{ false }; // every fixed-point value below 2^51: RoundSmall()
};

/** Projects placed points and adds them to the fixed-point sums. One instantiation per splat. */
template <typename TSplat>
class PointSplatter
{
public:
  PointSplatter(const DRRPointProjection & projection, const FixedPoint & fixedPoint, bool unbiased)
    : m_Projection(projection)
    , m_Columns(static_cast<int32_t>(projection.GetNumberOfColumns()))
    , m_Rows(static_cast<int32_t>(projection.GetNumberOfRows()))
    , m_SumScale(std::ldexp(1.0, fixedPoint.SumExponent))
    , m_SquareScale(std::ldexp(1.0, fixedPoint.SquareExponent))
    , m_SmallFixedPoint(fixedPoint.Small)
    , m_Unbiased(unbiased)
  {}

  /** Projects the batch's points and adds each to the fixed-point sums of its stratum (and to the sums of squares,
   * with one stratum): first the pixel and fixed-point value of every corner (a loop that vectorizes), then the
   * additions. */
  inline void
  ProjectAndSplat(uint64_t count, Batch & batch, uint64_t numberOfStrata, Accumulator & sums) const
  {
    m_Projection.ProjectBatch(count, batch.X, batch.Y, batch.Z, batch.Column, batch.Row, batch.Perspective);
    const bool squares = !sums.SumOfSquares.empty();
    // One loop per case, each free of calls and branches, so that it vectorizes.
    if (m_SmallFixedPoint)
    {
      squares ? this->PrepareCorners<true, true>(count, batch) : this->PrepareCorners<true, false>(count, batch);
    }
    else
    {
      squares ? this->PrepareCorners<false, true>(count, batch) : this->PrepareCorners<false, false>(count, batch);
    }
    constexpr unsigned int corners = TSplat::Corners;
    int64_t *              sumOfSquares = sums.SumOfSquares.data();
    uint64_t               landed = 0;
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

  /** ProjectAndSplat() for the points of a kept cloud (count of them from x, y, z, weight, stratum), in single
   * precision up to the fixed-point values (see DRRPointProjection::ProjectBatch()). A corner off the detector goes
   * to the trash slot past the pixels' sums (with value 0): the additions need no branch. */
  inline void
  ProjectAndSplatCloud(uint64_t        count,
                       const float *   x,
                       const float *   y,
                       const float *   z,
                       const float *   weight,
                       const uint8_t * stratum,
                       CloudBatch &    batch,
                       uint64_t        numberOfStrata,
                       Accumulator &   sums) const
  {
    m_Projection.ProjectBatch(count, x, y, z, batch.Column, batch.Row, batch.Perspective);
    const bool squares = !sums.SumOfSquares.empty();
    const auto strata = static_cast<int32_t>(numberOfStrata);
    uint64_t   landed;
    if (m_SmallFixedPoint)
    {
      landed = squares ? this->PrepareCloudCorners<true, true>(count, weight, stratum, strata, batch)
                       : this->PrepareCloudCorners<true, false>(count, weight, stratum, strata, batch);
    }
    else
    {
      landed = squares ? this->PrepareCloudCorners<false, true>(count, weight, stratum, strata, batch)
                       : this->PrepareCloudCorners<false, false>(count, weight, stratum, strata, batch);
    }
    sums.PointsOnDetector += landed;
    int64_t * sum = sums.Sum.data();
    for (unsigned int c = 0; c < TSplat::Corners; ++c)
    {
      Scatter(sum, batch.Index + c * samplesPerBatch, batch.Value + c * samplesPerBatch, count);
    }
    if (squares)
    {
      // One stratum: the index of a sum is its pixel's.
      for (unsigned int c = 0; c < TSplat::Corners; ++c)
      {
        Scatter(sums.SumOfSquares.data(), batch.Index + c * samplesPerBatch, batch.Square + c * samplesPerBatch, count);
      }
    }
  }

private:
  /** sum[index[s]] += value[s] for s < count, in four interleaved streams a quarter of the batch apart. Nearby points
   * often add to the same sum: in one stream, each addition would wait for the previous one's store; points a quarter
   * batch apart rarely share a pixel. Integer sums: the order changes nothing. */
  static void
  Scatter(int64_t * sum, const int32_t * index, const int64_t * value, uint64_t count)
  {
    const uint64_t quarter = count / 4;
    for (uint64_t s = 0; s < quarter; ++s)
    {
      sum[index[s]] += value[s];
      sum[index[s + quarter]] += value[s + quarter];
      sum[index[s + 2 * quarter]] += value[s + 2 * quarter];
      sum[index[s + 3 * quarter]] += value[s + 3 * quarter];
    }
    for (uint64_t s = 4 * quarter; s < count; ++s)
    {
      sum[index[s]] += value[s];
    }
  }

  /** The sum index and fixed-point value (and square) of every corner of every point of a cloud batch; returns the
   * number of points that reach the detector. The contribution is rounded to float, then scaled exactly (the scales
   * are powers of two) and rounded to fixed point in double; its square is exact in double. */
  template <bool VSmall, bool VSquares>
  inline uint64_t
  PrepareCloudCorners(uint64_t        count,
                      const float *   pointWeight,
                      const uint8_t * stratum,
                      int32_t         strata,
                      CloudBatch &    batch) const
  {
    constexpr unsigned int corners = TSplat::Corners;
    static_assert(corners <= maximumCorners, "CloudBatch holds at most maximumCorners corners per point");
    const bool    unbiased = m_Unbiased;
    const double  sumScale = m_SumScale;
    const double  squareScale = m_SquareScale;
    const int32_t columns = m_Columns;
    const int32_t rows = m_Rows;
    const int32_t trash = columns * rows * strata;
    // Widened in a loop of its own: bytes in the loop below keep it from vectorizing for AVX-512F (no byte vectors).
    for (uint64_t s = 0; s < count; ++s)
    {
      batch.Stratum[s] = stratum[s];
    }
    // Without the perspective weight, a factor 1 (exact): a select on unbiased in the loop below would not vectorize.
    if (!unbiased)
    {
      std::fill(batch.Perspective, batch.Perspective + count, 1.0f);
    }
    for (uint64_t s = 0; s < count; ++s)
    {
      // A point that does not count lands off the detector (and has perspective weight 0). Every load unconditional,
      // so that the selects need no branch.
      const float   ownWeight = pointWeight[s];
      const float   perspective = batch.Perspective[s];
      const float   weight = ownWeight * perspective;
      const int32_t ownStratum = batch.Stratum[s];
      int32_t       pixel[corners];
      float         share[corners];
      TSplat::Locate(batch.Column[s], batch.Row[s], columns, rows, pixel, share);
      for (unsigned int c = 0; c < corners; ++c)
      {
        const double contribution = static_cast<double>(weight * share[c]);
        batch.Index[c * samplesPerBatch + s] = pixel[c] >= 0 ? pixel[c] * strata + ownStratum : trash;
        batch.Value[c * samplesPerBatch + s] = Round<VSmall>(contribution * sumScale);
        batch.Square[c * samplesPerBatch + s] = VSquares ? Round<VSmall>(contribution * contribution * squareScale) : 0;
      }
    }
    // Counted in a loop of its own, from the indices: in the loop above, the count (or a test of the pixels) would
    // stop it from vectorizing.
    int32_t landed = 0;
    for (uint64_t s = 0; s < count; ++s)
    {
      int32_t reached = 0;
      for (unsigned int c = 0; c < corners; ++c)
      {
        reached |= static_cast<int32_t>(batch.Index[c * samplesPerBatch + s] != trash);
      }
      landed += reached;
    }
    return static_cast<uint64_t>(landed);
  }

  /** The pixel and fixed-point value (and square) of every corner of every point. */
  template <bool VSmall, bool VSquares>
  inline void
  PrepareCorners(uint64_t count, Batch & batch) const
  {
    constexpr unsigned int corners = TSplat::Corners;
    static_assert(corners <= maximumCorners, "Batch holds at most maximumCorners corners per point");
    const bool    unbiased = m_Unbiased;
    const double  sumScale = m_SumScale;
    const double  squareScale = m_SquareScale;
    const int32_t columns = m_Columns;
    const int32_t rows = m_Rows;
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
        batch.Value[corners * s + c] = Round<VSmall>(contribution * sumScale);
        batch.Square[corners * s + c] = VSquares ? Round<VSmall>(contribution * contribution * squareScale) : 0;
      }
    }
  }

  /** llrint(x). For |x| < 2^51 (VSmall): adding 1.5 2^52 rounds to the nearest integer (ties to even, as llrint) in
   * the low mantissa bits; this form vectorizes. */
  template <bool VSmall>
  static int64_t
  Round(double x)
  {
    if (VSmall)
    {
      const double shifted = x + 6755399441055744.0;
      int64_t      bits;
      std::memcpy(&bits, &shifted, sizeof(bits));
      return bits - 0x4338000000000000;
    }
    return std::llrint(x);
  }

  const DRRPointProjection & m_Projection;
  const int32_t              m_Columns;
  const int32_t              m_Rows;
  const double               m_SumScale;
  const double               m_SquareScale;
  const bool                 m_SmallFixedPoint;
  const bool                 m_Unbiased;
};

/** Does whole chunks of work; one instantiation per policy combination, chosen once per render or draw. */
class ChunkWorkBase
{
public:
  virtual ~ChunkWorkBase() = default;
  virtual void
  Run(uint64_t chunk, const Strata & strata, Worker & worker) const = 0;
};

/** A render that draws its points as it goes (nothing kept). */
template <typename TKernel, typename TSplat>
class DrawAndSplatChunks : public ChunkWorkBase
{
public:
  DrawAndSplatChunks(const PointDrawer<TKernel> & drawer, const PointSplatter<TSplat> & splatter)
    : m_Drawer(drawer), m_Splatter(splatter)
  {}
  void
  Run(uint64_t chunk, const Strata & strata, Worker & worker) const override
  {
    this->RunChunk(chunk, strata, worker);
  }

private:
  PointBasedDRR_VECTOR_CLONES void
  RunChunk(uint64_t chunk, const Strata & strata, Worker & worker) const
  {
    if (!worker.Scratch)
    {
      worker.Scratch.reset(new Batch);
    }
    Batch & batch = *worker.Scratch;
    m_Drawer.DrawChunk(chunk, strata, batch, [&](uint64_t, uint64_t count) {
      m_Splatter.ProjectAndSplat(count, batch, strata.GetNumberOfStrata(), worker.Sums);
    });
  }

  const PointDrawer<TKernel> &  m_Drawer;
  const PointSplatter<TSplat> & m_Splatter;
};

/** Draws points into a cloud (no sums). */
template <typename TKernel>
class DrawChunksIntoCloud : public ChunkWorkBase
{
public:
  DrawChunksIntoCloud(const PointDrawer<TKernel> & drawer, DRRPointCloud & cloud) : m_Drawer(drawer), m_Cloud(cloud) {}
  void
  Run(uint64_t chunk, const Strata & strata, Worker & worker) const override
  {
    if (!worker.Scratch)
    {
      worker.Scratch.reset(new Batch);
    }
    Batch &   batch = *worker.Scratch;
    float *   x = m_Cloud.GetX();
    float *   y = m_Cloud.GetY();
    float *   z = m_Cloud.GetZ();
    float *   weights = m_Cloud.GetWeights();
    uint8_t * stratum = m_Cloud.GetStrata();
    m_Drawer.DrawChunk(chunk, strata, batch, [&](uint64_t first, uint64_t count) {
      for (uint64_t s = 0; s < count; ++s)
      {
        x[first + s] = static_cast<float>(batch.X[s]);
        y[first + s] = static_cast<float>(batch.Y[s]);
        z[first + s] = static_cast<float>(batch.Z[s]);
      }
      if (weights)
      {
        std::transform(batch.Weight, batch.Weight + count, weights + first, [](double w) { return float(w); });
      }
      if (stratum)
      {
        std::transform(batch.Stratum, batch.Stratum + count, stratum + first, [](uint32_t r) { return uint8_t(r); });
      }
    });
  }

private:
  const PointDrawer<TKernel> & m_Drawer;
  DRRPointCloud &              m_Cloud;
};

/** A render of the points of a cloud. */
template <typename TSplat>
class SplatCloudChunks : public ChunkWorkBase
{
public:
  SplatCloudChunks(const DRRPointCloud & cloud, const PointSplatter<TSplat> & splatter)
    : m_Cloud(cloud), m_Splatter(splatter)
  {}
  void
  Run(uint64_t chunk, const Strata & strata, Worker & worker) const override
  {
    this->RunChunk(chunk, strata, worker);
  }

private:
  PointBasedDRR_VECTOR_CLONES void
  RunChunk(uint64_t chunk, const Strata & strata, Worker & worker) const
  {
    if (!worker.CloudScratch)
    {
      worker.CloudScratch.reset(new CloudBatch);
    }
    CloudBatch &    batch = *worker.CloudScratch;
    const uint64_t  end = std::min((chunk + 1) * DRRPointRenderer::SamplesPerChunk, strata.GetNumberOfSamples());
    const float *   weights = m_Cloud.GetWeights();
    const uint8_t * stratum = m_Cloud.GetStrata();
    // Absent weights and strata read as a batch of ones and of zeros: one loop for every cloud.
    static const std::vector<float>   ones(samplesPerBatch, 1.0f);
    static const std::vector<uint8_t> zeros(samplesPerBatch, 0);
    for (uint64_t first = chunk * DRRPointRenderer::SamplesPerChunk; first < end; first += samplesPerBatch)
    {
      const uint64_t count = std::min(samplesPerBatch, end - first);
      m_Splatter.ProjectAndSplatCloud(count,
                                      m_Cloud.GetX() + first,
                                      m_Cloud.GetY() + first,
                                      m_Cloud.GetZ() + first,
                                      weights ? weights + first : ones.data(),
                                      stratum ? stratum + first : zeros.data(),
                                      batch,
                                      strata.GetNumberOfStrata(),
                                      worker.Sums);
    }
  }

  const DRRPointCloud &         m_Cloud;
  const PointSplatter<TSplat> & m_Splatter;
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

namespace
{
/** The strata a sampler's points form in a render of settings.NumberOfSamples points. */
Strata
MakeStrata(const DRRPointSampler & sampler, const DRRPointRenderer::Settings & settings)
{
  // Dependent points (stratified, Markov chains): independent strata, whose spread gives the standard error.
  const uint64_t requestedStrata =
    settings.NumberOfStrata > 0 ? settings.NumberOfStrata : sampler.GetPreferredNumberOfStrata();
  const bool useStrata =
    !sampler.HasIndependentSamples() && requestedStrata > 1 && settings.NumberOfSamples >= 16 * requestedStrata;
  return Strata(settings.NumberOfSamples, useStrata ? requestedStrata : 1, sampler.InterleavesStrata());
}

/** Bounds the contributions so that the fixed-point sums cannot overflow. In perspective, the weight grows as
 * (SID / z)^2 near the source; if the points (inside the continuous-index box [lower, upper]) come that close, drops
 * those nearer than the depth that keeps at least 20 fractional bits (the dropped part of each ray is shorter than
 * that depth), through the projection's minimum depth, and says so in the result. */
FixedPoint
PlanFixedPoint(double                        numberOfSamples,
               double                        maximumWeight,
               const std::array<double, 3> & lower,
               const std::array<double, 3> & upper,
               bool                          unbiased,
               DRRPointProjection &          projection,
               DRRPointRenderer::Result &    result)
{
  const double N = numberOfSamples;
  double       contributionBound = maximumWeight;
  if (projection.IsPerspective() && unbiased)
  {
    double nearest, farthest;
    projection.ComputeDepthRange(lower, upper, nearest, farthest);
    const double sid = projection.GetSourceToDetectorDistance();
    const double obliquity = projection.GetMaximumObliquity();
    const double largestAffordableWeight = std::ldexp(1.0, 42) / (N * maximumWeight);
    const double depthCut = sid * std::sqrt(obliquity / largestAffordableWeight);
    // Only a volume whose depth range reaches into (0, depthCut) comes near the source; one wholly behind it does not.
    result.SourceNearVolume = nearest < depthCut && farthest > 0.0;
    const double minimumDepth = std::max(depthCut, nearest);
    projection.SetMinimumDepth(result.SourceNearVolume ? depthCut : 0.0);
    result.MinimumDepth = result.SourceNearVolume ? depthCut : 0.0;
    contributionBound *= (sid / minimumDepth) * (sid / minimumDepth) * obliquity;
  }
  FixedPoint fixedPoint;
  fixedPoint.SumExponent = FixedPointExponent(N, contributionBound);
  fixedPoint.SquareExponent = FixedPointExponent(N, contributionBound * contributionBound);
  // Each contribution is at most 2^62 / N in fixed point (both sums): below 2^51 from N = 2^11 on.
  fixedPoint.Small = N >= 4096.0;
  return fixedPoint;
}

/** Gives the workspace one worker per thread, whose sums (of numberOfPixels pixels, or none, and the trash slots)
 * are all zero; clears only what the last render did not leave cleared. */
void
PrepareWorkers(DRRPointRenderer::Workspace & workspace,
               const Strata &                strata,
               size_t                        numberOfPixels,
               MultiThreaderBase *           threader)
{
  const uint64_t numberOfChunks =
    (strata.GetNumberOfSamples() + DRRPointRenderer::SamplesPerChunk - 1) / DRRPointRenderer::SamplesPerChunk;
  // Past the pixels' sums, one trash slot per stratum, where corners off the detector add their 0 (see
  // ProjectAndSplatCloud()).
  const size_t sumSize = (numberOfPixels + 1) * strata.GetNumberOfStrata();
  const size_t squareSize = strata.GetNumberOfStrata() == 1 ? numberOfPixels + 1 : 0;
  workspace.Workers.resize(DRRWorkScheduler::GetNumberOfWorkers(threader, numberOfChunks));
  for (Worker & worker : workspace.Workers)
  {
    if (!workspace.Cleared || worker.Sums.Sum.size() != sumSize)
    {
      worker.Sums.Sum.assign(sumSize, 0);
    }
    if (!workspace.Cleared || worker.Sums.SumOfSquares.size() != squareSize)
    {
      worker.Sums.SumOfSquares.assign(squareSize, 0);
    }
    worker.Sums.PointsOnDetector = 0;
  }
  workspace.Cleared = false; // until a reduction clears the sums again
}

/** Runs work over every chunk of the strata's samples, with one worker of the workspace per thread. */
void
RunChunks(const ChunkWorkBase &         work,
          const Strata &                strata,
          DRRPointRenderer::Workspace & workspace,
          MultiThreaderBase *           threader,
          ProcessObject *               progressFilter)
{
  const uint64_t numberOfChunks =
    (strata.GetNumberOfSamples() + DRRPointRenderer::SamplesPerChunk - 1) / DRRPointRenderer::SamplesPerChunk;
  std::vector<Worker> & workers = workspace.Workers;
  DRRWorkScheduler::Run(
    threader,
    numberOfChunks,
    [&](unsigned int worker, uint64_t chunk) { work.Run(chunk, strata, workers[worker]); },
    progressFilter);
}

/** total[i] += sum[i], sum[i] = 0 for i < n. */
PointBasedDRR_VECTOR_CLONES void
AddAndClear(int64_t * __restrict__ sum, int64_t * __restrict__ total, size_t n)
{
  for (size_t i = 0; i < n; ++i)
  {
    total[i] += sum[i];
    sum[i] = 0;
  }
}

struct ReduceConstants
{
  double N;                  // samples
  double ValueScale;         // M / (N a)
  double InverseSumScale;    // of the fixed point
  double InverseSquareScale; // of the fixed point
};

/** The line integrals and standard errors of n pixels from their integer sums (pixel major, as the workers'). Each
 * step a loop over the pixels, so that it vectorizes; every pixel adds its terms in the same order as one loop over
 * its strata would. */
PointBasedDRR_VECTOR_CLONES void
ReducePixels(const int64_t *         total,
             const int64_t *         totalOfSquares,
             size_t                  n,
             uint64_t                numberOfStrata,
             const double *          stratumScale,
             const ReduceConstants & constants,
             double * __restrict__ lineIntegral,
             double * __restrict__ standardError)
{
  const double        N = constants.N;
  std::vector<double> stratumSums(n * numberOfStrata); // stratum major
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    double * __restrict__ stratumSum = stratumSums.data() + r * n;
    for (size_t p = 0; p < n; ++p)
    {
      stratumSum[p] = static_cast<double>(total[p * numberOfStrata + r]) * constants.InverseSumScale;
    }
  }
  std::vector<double> sums(n, 0.0);
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    const double * stratumSum = stratumSums.data() + r * n;
    for (size_t p = 0; p < n; ++p)
    {
      sums[p] += stratumSum[p];
    }
  }
  for (size_t p = 0; p < n; ++p)
  {
    lineIntegral[p] = constants.ValueScale * sums[p];
  }
  if (numberOfStrata == 1)
  {
    for (size_t p = 0; p < n; ++p)
    {
      const double s = sums[p];
      const double s2 = static_cast<double>(totalOfSquares[p]) * constants.InverseSquareScale;
      const double variance = N > 1.0 ? N / (N - 1.0) * std::max(0.0, s2 - s * s / N) : s2;
      standardError[p] = constants.ValueScale * std::sqrt(variance);
    }
    return;
  }
  // Each stratum is an independent estimate L_r = M / (n_r a) S_r of the same image; the variance of their
  // combination is estimated from their spread.
  std::vector<double> squaredDeviations(n, 0.0);
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    const double * stratumSum = stratumSums.data() + r * n;
    const double   scale = stratumScale[r];
    for (size_t p = 0; p < n; ++p)
    {
      const double estimate = scale * stratumSum[p];
      squaredDeviations[p] += (estimate - lineIntegral[p]) * (estimate - lineIntegral[p]);
    }
  }
  const double pairs = numberOfStrata * (numberOfStrata - 1.0);
  for (size_t p = 0; p < n; ++p)
  {
    standardError[p] = std::sqrt(squaredDeviations[p] / pairs);
  }
}

/** Integer reduction of the workers' sums into the line integrals and their standard errors: exact, hence
 * independent of the order and of the worker that held each chunk. Blocks of pixels in parallel (each pixel on its
 * own: the same bits on any number of threads); each sum is cleared as it is read, for the workspace's next render. */
void
Reduce(DRRPointRenderer::Workspace & workspace,
       const Strata &                strata,
       const FixedPoint &            fixedPoint,
       double                        pixelArea,
       MultiThreaderBase *           threader,
       DRRPointRenderer::Result &    result)
{
  std::vector<Worker> & workers = workspace.Workers;
  const uint64_t        numberOfStrata = strata.GetNumberOfStrata();
  const double          N = static_cast<double>(strata.GetNumberOfSamples());
  const double          valueScale = result.SampledRoomMass / (N * pixelArea);
  const double          inverseSumScale = std::ldexp(1.0, -fixedPoint.SumExponent);
  const double          inverseSquareScale = std::ldexp(1.0, -fixedPoint.SquareExponent);
  std::vector<double>   stratumScale(numberOfStrata); // M / (n_r a), the same for every pixel
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    stratumScale[r] = result.SampledRoomMass / (strata.Size(r) * pixelArea);
  }
  const ReduceConstants constants{ N, valueScale, inverseSumScale, inverseSquareScale };
  const size_t          numberOfPixels = result.LineIntegral.size();
  const auto            reduceBlock = [&](size_t firstPixel, size_t endPixel) {
    // First the workers' sums of the block, added (and cleared) in one pass over contiguous memory, then the pixels.
    std::vector<int64_t> total((endPixel - firstPixel) * numberOfStrata, 0);
    std::vector<int64_t> totalOfSquares(numberOfStrata == 1 ? endPixel - firstPixel : 0, 0);
    for (Worker & worker : workers)
    {
      AddAndClear(worker.Sums.Sum.data() + firstPixel * numberOfStrata, total.data(), total.size());
      if (numberOfStrata == 1)
      {
        AddAndClear(worker.Sums.SumOfSquares.data() + firstPixel, totalOfSquares.data(), totalOfSquares.size());
      }
    }
    ReducePixels(total.data(),
                 totalOfSquares.data(),
                 endPixel - firstPixel,
                 numberOfStrata,
                 stratumScale.data(),
                 constants,
                 result.LineIntegral.data() + firstPixel,
                 result.StandardError.data() + firstPixel);
  };
  constexpr size_t pixelsPerBlock = 2048;
  const size_t     numberOfBlocks = (numberOfPixels + pixelsPerBlock - 1) / pixelsPerBlock;
  if (numberOfBlocks > 1)
  {
    threader->ParallelizeArray(
      0,
      numberOfBlocks,
      [&](SizeValueType block) {
        reduceBlock(block * pixelsPerBlock, std::min(numberOfPixels, (block + 1) * pixelsPerBlock));
      },
      nullptr);
  }
  else
  {
    reduceBlock(0, numberOfPixels);
  }
  result.NumberOfStrata = numberOfStrata;
  result.NumberOfSamples = strata.GetNumberOfSamples();
  for (Worker & worker : workers)
  {
    result.PointsOnDetector += worker.Sums.PointsOnDetector;
    // The trash slots, past the pixels.
    std::fill(worker.Sums.Sum.begin() + numberOfPixels * numberOfStrata, worker.Sums.Sum.end(), 0);
    std::fill(worker.Sums.SumOfSquares.begin() + std::min(numberOfPixels, worker.Sums.SumOfSquares.size()),
              worker.Sums.SumOfSquares.end(),
              0);
  }
  workspace.Cleared = true;
}

/** A result of zeros for the projection's detector. */
DRRPointRenderer::Result
ZeroResult(const DRRPointProjection & projection)
{
  const size_t numberOfPixels =
    static_cast<size_t>(projection.GetNumberOfColumns()) * static_cast<size_t>(projection.GetNumberOfRows());
  DRRPointRenderer::Result result;
  result.LineIntegral.assign(numberOfPixels, 0.0);
  result.StandardError.assign(numberOfPixels, 0.0);
  return result;
}

double
KernelReach(PointBasedDRREnums::ReconstructionKernel kernel)
{
  return WithKernel(kernel, [](auto policy) { return decltype(policy)::Reach; });
}
} // namespace

void
DRRPointRenderer::ComputeKernelSupport(const DRRAttenuationVolume & volume,
                                       KernelEnum                   kernel,
                                       std::array<double, 3> &      lower,
                                       std::array<double, 3> &      upper)
{
  const double reach = KernelReach(kernel);
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
  Result result = ZeroResult(projection);
  result.RoomMass = sampler.GetTotalMass() * projection.GetRoomMassScale();
  if (!(result.RoomMass > 0.0))
  {
    return result; // all air: the exact answer is a zero image
  }
  // Sample only what can reach the detector (for samplers that cull).
  const double splatReach = WithSplat(settings.Splat, [](auto policy) { return decltype(policy)::Reach; });
  sampler.SetView(&projection, KernelReach(settings.Kernel), splatReach);
  result.SampledRoomMass = sampler.GetSampledMass() * projection.GetRoomMassScale();
  if (!(result.SampledRoomMass > 0.0))
  {
    return result; // nothing in view: the exact answer is a zero image
  }

  const Strata          strata = MakeStrata(sampler, settings);
  std::array<double, 3> lower, upper;
  ComputeKernelSupport(volume, settings.Kernel, lower, upper);
  const FixedPoint fixedPoint = PlanFixedPoint(static_cast<double>(strata.GetNumberOfSamples()),
                                               sampler.GetMaximumWeight(),
                                               lower,
                                               upper,
                                               settings.Weighting == WeightingEnum::Unbiased,
                                               projection,
                                               result);
  Workspace        workspace;
  PrepareWorkers(workspace, strata, result.LineIntegral.size(), threader);
  WithKernel(settings.Kernel, [&](auto kernel) {
    return WithSplat(settings.Splat, [&](auto splat) {
      const PointDrawer<decltype(kernel)>  drawer(volume, sampler, settings.Seed);
      const PointSplatter<decltype(splat)> splatter(
        projection, fixedPoint, settings.Weighting == WeightingEnum::Unbiased);
      const DrawAndSplatChunks<decltype(kernel), decltype(splat)> work(drawer, splatter);
      RunChunks(work, strata, workspace, threader, progressFilter);
      return 0;
    });
  });
  Reduce(workspace, strata, fixedPoint, projection.GetPixelArea(), threader, result);
  return result;
}

std::shared_ptr<DRRPointRenderer::Workspace>
DRRPointRenderer::MakeWorkspace()
{
  return std::make_shared<Workspace>();
}

DRRPointCloud::Pointer
DRRPointRenderer::Draw(const DRRAttenuationVolume & volume,
                       DRRPointSampler &            sampler,
                       const Settings &             settings,
                       MultiThreaderBase *          threader,
                       ProcessObject *              progressFilter)
{
  if (settings.NumberOfSamples == 0)
  {
    itkGenericExceptionMacro("DRRPointRenderer: the number of samples must be at least 1");
  }
  sampler.SetView(nullptr, 0.0, 0.0); // every pose: the whole volume
  const Strata               strata = MakeStrata(sampler, settings);
  DRRPointCloud::Description description;
  description.NumberOfRequestedSamples = settings.NumberOfSamples;
  description.NumberOfStrata = strata.GetNumberOfStrata();
  description.InterleavedStrata = strata.IsInterleaved();
  description.SampledMass = sampler.GetSampledMass();
  description.MaximumWeight = sampler.GetMaximumWeight();
  description.Kernel = settings.Kernel;
  ComputeKernelSupport(volume, settings.Kernel, description.SupportLower, description.SupportUpper);
  description.VolumeSize = { volume.GetSize()[0], volume.GetSize()[1], volume.GetSize()[2] };
  description.Seed = settings.Seed;
  auto cloud = DRRPointCloud::New();
  if (!(description.SampledMass > 0.0))
  {
    cloud->Allocate(0, false, false, description); // all air: no points, zero images
    return cloud;
  }
  cloud->Allocate(
    strata.GetNumberOfSamples(), sampler.GetMaximumWeight() != 1.0, strata.GetNumberOfStrata() > 1, description);
  Workspace workspace;
  PrepareWorkers(workspace, strata, 0, threader);
  WithKernel(settings.Kernel, [&](auto kernel) {
    const PointDrawer<decltype(kernel)>         drawer(volume, sampler, settings.Seed);
    const DrawChunksIntoCloud<decltype(kernel)> work(drawer, *cloud);
    RunChunks(work, strata, workspace, threader, progressFilter);
    return 0;
  });
  return cloud;
}

DRRPointRenderer::Result
DRRPointRenderer::Render(const DRRPointCloud & cloud,
                         DRRPointProjection    projection,
                         const Settings &      settings,
                         MultiThreaderBase *   threader,
                         ProcessObject *       progressFilter,
                         Workspace *           workspace)
{
  const DRRPointCloud::Description & description = cloud.GetDescription();
  Result                             result = ZeroResult(projection);
  result.RoomMass = description.SampledMass * projection.GetRoomMassScale();
  result.SampledRoomMass = result.RoomMass;
  if (!(result.RoomMass > 0.0) || cloud.GetNumberOfPoints() == 0)
  {
    return result; // all air: the exact answer is a zero image
  }
  const Strata strata(description.NumberOfRequestedSamples, description.NumberOfStrata, description.InterleavedStrata);
  if (strata.GetNumberOfSamples() != cloud.GetNumberOfPoints())
  {
    itkGenericExceptionMacro("DRRPointRenderer: the point cloud's description does not match its points");
  }
  const bool       unbiased = settings.Weighting == WeightingEnum::Unbiased;
  const FixedPoint fixedPoint = PlanFixedPoint(static_cast<double>(strata.GetNumberOfSamples()),
                                               description.MaximumWeight,
                                               description.SupportLower,
                                               description.SupportUpper,
                                               unbiased,
                                               projection,
                                               result);
  Workspace        ownWorkspace;
  Workspace &      kept = workspace ? *workspace : ownWorkspace;
  PrepareWorkers(kept, strata, result.LineIntegral.size(), threader);
  WithSplat(settings.Splat, [&](auto splat) {
    const PointSplatter<decltype(splat)>    splatter(projection, fixedPoint, unbiased);
    const SplatCloudChunks<decltype(splat)> work(cloud, splatter);
    RunChunks(work, strata, kept, threader, progressFilter);
    return 0;
  });
  Reduce(kept, strata, fixedPoint, projection.GetPixelArea(), threader, result);
  return result;
}
} // namespace itk
