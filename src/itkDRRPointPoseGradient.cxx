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
#include "itkDRRPointPoseGradient.h"
#include "itkDRRPointRenderer.h"
#include "itkDRRCompilerBuiltins.h"
#include "itkDRRWorkScheduler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace itk
{
namespace
{
constexpr uint64_t batchSize = 512;
constexpr unsigned lanes = 16; // independent partial sums: vectorizable, and the same bits on any instruction set
constexpr unsigned terms = 13; // Phi, a alpha (3), a alpha q^T (9)

/** The beam a backward pass differentiates: a cone, a localizer (a fan across, parallel along the rows) or parallel. */
enum class Beam
{
  Cone,
  Localizer,
  Parallel
};

/** G, padded by zeros so that the four corners of any clamped position are inside: column c of the detector is
 * column c + 1 here, and there are columns + 3 columns and rows + 3 rows. */
struct PaddedImage
{
  std::vector<float> Values;
  int32_t            Columns, Rows, Stride;
};

PaddedImage
Pad(const double * image, int32_t columns, int32_t rows)
{
  PaddedImage padded{ std::vector<float>(static_cast<size_t>(columns + 3) * static_cast<size_t>(rows + 3), 0.0f),
                      columns,
                      rows,
                      columns + 3 };
  for (int32_t r = 0; r < rows; ++r)
  {
    for (int32_t c = 0; c < columns; ++c)
    {
      padded.Values[static_cast<size_t>(r + 1) * padded.Stride + c + 1] = static_cast<float>(image[r * columns + c]);
    }
  }
  return padded;
}

/** One batch: the points' positions relative to the volume's centre, and what each adds to the sums. */
struct Batch
{
  float Column[batchSize], Row[batchSize];
  float A[batchSize];      // w g / z (or w for parallel), 0 for a point that does not count
  float Weight[batchSize]; // w g: the point's value share
  float TU[batchSize], TV[batchSize], Depth[batchSize];
  float G[batchSize], GC[batchSize], GR[batchSize]; // G^ and its derivatives along columns and rows
  float Alpha[3][batchSize];
  float Q[3][batchSize];
  float Term[terms][batchSize];
};

/** What a chunk adds up, in lanes: Phi, sum a alpha (3), sum a alpha q^T (9). */
struct LaneSums
{
  double   Total[terms][lanes]{};
  uint64_t OnDetector{ 0 };
};

/** The parts of the projection the pass needs, in float (the render of a cloud projects in float). */
struct Coefficients
{
  float PU0, GU[3], PV0, GV[3], Z0, GZ[3];
  float SID, SIDOverDU, SIDOverDV, InverseDU, InverseDV, ColumnShift, RowShift, MinimumDepth;
  float Center[3];
  bool  Unbiased;
};

template <Beam VBeam>
PointBasedDRR_VECTOR_CLONES void
RunBatch(const Coefficients & k,
         const PaddedImage &  G,
         const float *        x,
         const float *        y,
         const float *        z,
         const float *        pointWeight,
         float                scale,
         uint64_t             n,
         Batch &              b,
         LaneSums &           sums)
{
  // Locals, so that the compiler knows the batch's stores do not change them (and keeps them in registers): the loops
  // below then vectorize.
  const float pu0 = k.PU0, gu0 = k.GU[0], gu1 = k.GU[1], gu2 = k.GU[2];
  const float pv0 = k.PV0, gv0 = k.GV[0], gv1 = k.GV[1], gv2 = k.GV[2];
  const float z0 = k.Z0, gz0 = k.GZ[0], gz1 = k.GZ[1], gz2 = k.GZ[2];
  const float sid = k.SID, sidOverDU = k.SIDOverDU, sidOverDV = k.SIDOverDV, inverseDU = k.InverseDU,
              inverseDV = k.InverseDV, columnShift = k.ColumnShift, rowShift = k.RowShift,
              minimumDepth = k.MinimumDepth;
  const float cx = k.Center[0], cy = k.Center[1], cz = k.Center[2];
  // 1 or 0: the perspective weight and its derivative, or none (the paper's count), without a branch.
  const float unbiased = k.Unbiased ? 1.0f : 0.0f;
  // 1. Project (as DRRPointProjection::ProjectBatch<float> does), branch-free.
  for (uint64_t s = 0; s < n; ++s)
  {
    const float pu = pu0 + gu0 * x[s] + gu1 * y[s] + gu2 * z[s];
    const float pv = pv0 + gv0 * x[s] + gv1 * y[s] + gv2 * z[s];
    const float w = scale * pointWeight[s];
    b.Q[0][s] = x[s] - cx;
    b.Q[1][s] = y[s] - cy;
    b.Q[2][s] = z[s] - cz;
    if (VBeam == Beam::Parallel)
    {
      b.Column[s] = pu * inverseDU + columnShift;
      b.Row[s] = pv * inverseDV + rowShift;
      b.Weight[s] = w;
      b.A[s] = w;
    }
    else
    {
      const float depth = z0 + gz0 * x[s] + gz1 * y[s] + gz2 * z[s];
      const bool  counts = (depth >= minimumDepth) & (depth <= sid);
      const float inverseZ = 1.0f / depth;
      const float tu = pu * inverseZ, tv = pv * inverseZ;
      const float magnification = sid * inverseZ;
      // The perspective weight g, or 1: a cone's (SID / z)^2 sqrt(1 + tu^2 + tv^2), a localizer's (SID / z)
      // sqrt(1 + tu^2).
      const float g =
        VBeam == Beam::Cone
          ? unbiased * magnification * magnification * std::sqrt(1.0f + tu * tu + tv * tv) + 1.0f - unbiased
          : unbiased * magnification * std::sqrt(1.0f + tu * tu) + 1.0f - unbiased;
      b.Row[s] = VBeam == Beam::Cone ? tv * sidOverDV + rowShift : pv * inverseDV + rowShift;
      b.Column[s] = counts ? tu * sidOverDU + columnShift : -4.0f;
      b.TU[s] = tu;
      b.TV[s] = tv;
      b.Depth[s] = depth;
      b.Weight[s] = counts ? w * g : 0.0f;
      b.A[s] = counts ? w * g * inverseZ : 0.0f;
    }
  }
  // 2. Read G bilinearly where the splat puts each point, with its derivatives (clamped as the splat clamps), and count
  // the points with a corner on the detector.
  const float   maxColumn = static_cast<float>(G.Columns + 1), maxRow = static_cast<float>(G.Rows + 1);
  const float * values = G.Values.data();
  const int32_t stride = G.Stride, columns = G.Columns, rows = G.Rows;
  int32_t       onDetector = 0;
  for (uint64_t s = 0; s < n; ++s)
  {
    const float   cs = std::min(maxColumn, std::max(0.0f, b.Column[s] + 1.0f));
    const float   rs = std::min(maxRow, std::max(0.0f, b.Row[s] + 1.0f));
    const int32_t c0 = static_cast<int32_t>(cs), r0 = static_cast<int32_t>(rs);
    const float   fc = cs - static_cast<float>(c0), fr = rs - static_cast<float>(r0);
    const int32_t at = r0 * stride + c0;
    const float   g00 = values[at], g10 = values[at + 1], g01 = values[at + stride], g11 = values[at + stride + 1];
    b.G[s] = (1.0f - fr) * ((1.0f - fc) * g00 + fc * g10) + fr * ((1.0f - fc) * g01 + fc * g11);
    b.GC[s] = (1.0f - fr) * (g10 - g00) + fr * (g11 - g01);
    b.GR[s] = (1.0f - fc) * (g01 - g00) + fc * (g11 - g10);
  }
  // Counted in a loop of its own (in the one above, it keeps the gathers from vectorizing).
  const float lastColumn = static_cast<float>(columns), lastRow = static_cast<float>(rows);
  for (uint64_t s = 0; s < n; ++s)
  {
    onDetector += static_cast<int32_t>((b.A[s] != 0.0f) & (b.Column[s] > -1.0f) & (b.Row[s] > -1.0f) &
                                       (b.Column[s] < lastColumn) & (b.Row[s] < lastRow));
  }
  sums.OnDetector += static_cast<uint64_t>(onDetector);
  // 3. dPhi/dy = a (alpha_u u + alpha_v v + alpha_n n): the splat's move (grad G^ J_u) and, unbiased, the perspective
  // weight's change (G^ grad g), with d depth / dy = -n and d tu / dy = (u + tu n) / z.
  for (uint64_t s = 0; s < n; ++s)
  {
    if (VBeam == Beam::Parallel)
    {
      b.Alpha[0][s] = b.GC[s] * inverseDU;
      b.Alpha[1][s] = b.GR[s] * inverseDV;
      b.Alpha[2][s] = 0.0f;
    }
    else
    {
      const float tu = b.TU[s], tv = b.TV[s];
      const float h = unbiased * b.G[s]; // the weight's derivative, none for the paper's count
      const float gc = b.GC[s] * sidOverDU;
      if (VBeam == Beam::Cone)
      {
        const float s2 = 1.0f + tu * tu + tv * tv;
        const float gr = b.GR[s] * sidOverDV;
        b.Alpha[0][s] = h * tu / s2 + gc;
        b.Alpha[1][s] = h * tv / s2 + gr;
        b.Alpha[2][s] = h * (2.0f + (tu * tu + tv * tv) / s2) + gc * tu + gr * tv;
      }
      else
      {
        const float s2 = 1.0f + tu * tu;
        b.Alpha[0][s] = h * tu / s2 + gc;
        b.Alpha[1][s] = b.GR[s] * inverseDV * b.Depth[s];
        b.Alpha[2][s] = h * (1.0f + tu * tu / s2) + gc * tu;
      }
    }
  }
  // 4. Each point's thirteen terms (Phi, a alpha, a alpha q^T) in single precision, a loop that vectorizes.
  for (uint64_t s = 0; s < n; ++s)
  {
    const float a = b.A[s];
    b.Term[0][s] = b.Weight[s] * b.G[s];
    for (unsigned r = 0; r < 3; ++r)
    {
      const float aa = a * b.Alpha[r][s];
      b.Term[1 + r][s] = aa;
      for (unsigned c = 0; c < 3; ++c)
      {
        b.Term[4 + 3 * r + c][s] = aa * b.Q[c][s];
      }
    }
  }
  // 5. Added up: point s to lane s % lanes in single precision over the batch (32 terms a lane, rounding below
  // 1e-6 of the sum), the lanes' totals to double. A fixed order: the same bits on any instruction set.
  for (unsigned t = 0; t < terms; ++t)
  {
    float          lane[lanes] = {};
    const float *  term = b.Term[t];
    const uint64_t whole = n - n % lanes;
    for (uint64_t s = 0; s < whole; s += lanes)
    {
      for (unsigned l = 0; l < lanes; ++l)
      {
        lane[l] += term[s + l];
      }
    }
    for (uint64_t s = whole; s < n; ++s)
    {
      lane[s - whole] += term[s];
    }
    for (unsigned l = 0; l < lanes; ++l)
    {
      sums.Total[t][l] += static_cast<double>(lane[l]);
    }
  }
}
} // namespace

DRRPointPoseGradient::Moments
DRRPointPoseGradient::Compute(const DRRPointCloud &      cloud,
                              const DRRPointProjection & projection,
                              WeightingEnum              weighting,
                              const double *             pixelWeights,
                              MultiThreaderBase *        threader)
{
  const DRRPointCloud::Description & description = cloud.GetDescription();
  const double                       p0[3] = { 0.5 * (static_cast<double>(description.VolumeSize[0]) - 1.0),
                                               0.5 * (static_cast<double>(description.VolumeSize[1]) - 1.0),
                                               0.5 * (static_cast<double>(description.VolumeSize[2]) - 1.0) };
  Moments                            moments;
  moments.Reference = projection.IndexToRoom(p0);
  moments.Moment.Fill(0.0);
  const uint64_t numberOfPoints = cloud.GetNumberOfPoints();
  const double   roomMass = description.SampledMass * projection.GetRoomMassScale();
  if (numberOfPoints == 0 || !(roomMass > 0.0))
  {
    return moments;
  }
  const DRRPointProjection & P = projection;
  Coefficients               k;
  k.PU0 = static_cast<float>(P.m_PU0);
  k.PV0 = static_cast<float>(P.m_PV0);
  k.Z0 = static_cast<float>(P.m_Z0);
  for (unsigned int a = 0; a < 3; ++a)
  {
    k.GU[a] = static_cast<float>(P.m_GU[a]);
    k.GV[a] = static_cast<float>(P.m_GV[a]);
    k.GZ[a] = static_cast<float>(P.m_GZ[a]);
    k.Center[a] = static_cast<float>(p0[a]);
  }
  k.SID = static_cast<float>(P.m_SID);
  k.SIDOverDU = static_cast<float>(P.m_SIDOverDU);
  k.SIDOverDV = static_cast<float>(P.m_SIDOverDV);
  k.InverseDU = static_cast<float>(P.m_InverseDU);
  k.InverseDV = static_cast<float>(P.m_InverseDV);
  k.ColumnShift = static_cast<float>(P.m_ColumnShift);
  k.RowShift = static_cast<float>(P.m_RowShift);
  // Rounded up, as the render rounds it: no point nearer than the minimum depth counts.
  k.MinimumDepth = static_cast<float>(P.m_MinimumDepth);
  if (static_cast<double>(k.MinimumDepth) < P.m_MinimumDepth)
  {
    k.MinimumDepth = std::nextafter(k.MinimumDepth, std::numeric_limits<float>::infinity());
  }
  k.Unbiased = weighting == WeightingEnum::Unbiased;
  const Beam        beam = !P.m_Perspective ? Beam::Parallel : (P.m_MagnifiesRows ? Beam::Cone : Beam::Localizer);
  const PaddedImage G = Pad(pixelWeights, static_cast<int32_t>(P.m_Columns), static_cast<int32_t>(P.m_Rows));
  const float       scale = static_cast<float>(roomMass / (static_cast<double>(numberOfPoints) * P.GetPixelArea()));
  const float *     weights = cloud.GetWeights();
  // Absent weights read as a batch of ones: one loop for every cloud.
  static const std::vector<float> ones(batchSize, 1.0f);
  const uint64_t                  chunkSize = DRRPointRenderer::SamplesPerChunk;
  const uint64_t                  numberOfChunks = (numberOfPoints + chunkSize - 1) / chunkSize;
  std::vector<LaneSums>           sums(numberOfChunks);

  const auto chunk = [&](unsigned int, uint64_t c) {
    LaneSums &             own = sums[c];
    std::unique_ptr<Batch> batch(new Batch);
    const uint64_t         end = std::min(numberOfPoints, (c + 1) * chunkSize);
    for (uint64_t first = c * chunkSize; first < end; first += batchSize)
    {
      const uint64_t n = std::min(batchSize, end - first);
      const float *  w = weights ? weights + first : ones.data();
      const float *  X = cloud.GetX() + first;
      const float *  Y = cloud.GetY() + first;
      const float *  Z = cloud.GetZ() + first;
      switch (beam)
      {
        case Beam::Cone:
          RunBatch<Beam::Cone>(k, G, X, Y, Z, w, scale, n, *batch, own);
          break;
        case Beam::Localizer:
          RunBatch<Beam::Localizer>(k, G, X, Y, Z, w, scale, n, *batch, own);
          break;
        case Beam::Parallel:
          RunBatch<Beam::Parallel>(k, G, X, Y, Z, w, scale, n, *batch, own);
          break;
      }
    }
  };
  DRRWorkScheduler::Run(threader, numberOfChunks, chunk, nullptr);

  // Chunks, then lanes, in order: the same bits on any number of threads.
  double   value = 0.0, alpha[3] = { 0.0, 0.0, 0.0 }, alphaQ[3][3] = { { 0.0 } };
  uint64_t onDetector = 0;
  for (const LaneSums & own : sums)
  {
    onDetector += own.OnDetector;
    for (unsigned l = 0; l < lanes; ++l)
    {
      value += own.Total[0][l];
      for (unsigned r = 0; r < 3; ++r)
      {
        alpha[r] += own.Total[1 + r][l];
        for (unsigned c = 0; c < 3; ++c)
        {
          alphaQ[r][c] += own.Total[4 + 3 * r + c][l];
        }
      }
    }
  }
  // From the beam's frame to the room: Sum = E alpha, Moment = E (alpha q^T) F^T, E = [u v n], F the index-to-room
  // matrix (y - Reference = F q).
  const VectorType frame[3] = { P.m_U, P.m_V, P.m_Normal };
  for (unsigned int r = 0; r < 3; ++r)
  {
    moments.Sum += frame[r] * alpha[r];
  }
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      double m = 0.0;
      for (unsigned int r = 0; r < 3; ++r)
      {
        for (unsigned int c = 0; c < 3; ++c)
        {
          m += frame[r][i] * alphaQ[r][c] * P.m_IndexToRoom[j][c];
        }
      }
      moments.Moment[i][j] = m;
    }
  }
  moments.Value = value;
  moments.PointsOnDetector = onDetector;
  return moments;
}
} // namespace itk
