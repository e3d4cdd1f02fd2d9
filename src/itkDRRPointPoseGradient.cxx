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
#include "itkDRRWorkScheduler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace itk
{
namespace
{
/** What one chunk of points adds up: Phi, the sums of a alpha (3) and of a alpha (p - p_ref)^T (9), in the beam's
 * frame (u, v, n) by the volume's index axes, and the points on the detector. */
struct ChunkSums
{
  double   Value{ 0.0 };
  double   Alpha[3]{ 0.0, 0.0, 0.0 };
  double   AlphaIndex[3][3]{ { 0.0, 0.0, 0.0 }, { 0.0, 0.0, 0.0 }, { 0.0, 0.0, 0.0 } };
  uint64_t OnDetector{ 0 };
};

/** G read at a continuous pixel position as the bilinear splat deposits there: its value and its derivatives along
 * the columns and the rows (pixels off the detector read 0). */
struct BilinearRead
{
  double Value, AlongColumns, AlongRows;
  bool   OnDetector;
};

BilinearRead
ReadBilinear(const double * image, int64_t columns, int64_t rows, double column, double row)
{
  const double  c = std::floor(column), r = std::floor(row);
  const double  fc = column - c, fr = row - r;
  const int64_t c0 = static_cast<int64_t>(std::max(-2.0, std::min(c, static_cast<double>(columns + 1))));
  const int64_t r0 = static_cast<int64_t>(std::max(-2.0, std::min(r, static_cast<double>(rows + 1))));
  const auto    at = [&](int64_t i, int64_t j) {
    return i >= 0 && j >= 0 && i < columns && j < rows ? image[j * columns + i] : 0.0;
  };
  const double g00 = at(c0, r0), g10 = at(c0 + 1, r0), g01 = at(c0, r0 + 1), g11 = at(c0 + 1, r0 + 1);
  const bool   onDetector =
    c0 + 1 >= 0 && r0 + 1 >= 0 && c0 < columns && r0 < rows && std::isfinite(column) && std::isfinite(row);
  if (!onDetector)
  {
    return { 0.0, 0.0, 0.0, false };
  }
  return { (1.0 - fc) * (1.0 - fr) * g00 + fc * (1.0 - fr) * g10 + (1.0 - fc) * fr * g01 + fc * fr * g11,
           (1.0 - fr) * (g10 - g00) + fr * (g11 - g01),
           (1.0 - fc) * (g01 - g00) + fc * (g11 - g10),
           true };
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
  const double               scale = roomMass / (static_cast<double>(numberOfPoints) * projection.GetPixelArea());
  const bool                 unbiased = weighting == WeightingEnum::Unbiased;
  const DRRPointProjection & P = projection;
  const int64_t              columns = P.m_Columns, rows = P.m_Rows;
  const float *              X = cloud.GetX();
  const float *              Y = cloud.GetY();
  const float *              Z = cloud.GetZ();
  const float *              weights = cloud.GetWeights();
  const uint64_t             chunkSize = DRRPointRenderer::SamplesPerChunk;
  const uint64_t             numberOfChunks = (numberOfPoints + chunkSize - 1) / chunkSize;
  std::vector<ChunkSums>     sums(numberOfChunks);

  const auto chunk = [&](unsigned int, uint64_t k) {
    ChunkSums &    own = sums[k];
    const uint64_t end = std::min(numberOfPoints, (k + 1) * chunkSize);
    for (uint64_t i = k * chunkSize; i < end; ++i)
    {
      const double p[3] = { X[i], Y[i], Z[i] };
      const double pu = P.m_PU0 + P.m_GU[0] * p[0] + P.m_GU[1] * p[1] + P.m_GU[2] * p[2];
      const double pv = P.m_PV0 + P.m_GV[0] * p[0] + P.m_GV[1] * p[1] + P.m_GV[2] * p[2];
      const double w = scale * (weights ? static_cast<double>(weights[i]) : 1.0);
      double       column, row, g, a, alpha[3];
      if (!P.m_Perspective)
      {
        column = pu * P.m_InverseDU + P.m_ColumnShift;
        row = pv * P.m_InverseDV + P.m_RowShift;
        const BilinearRead G = ReadBilinear(pixelWeights, columns, rows, column, row);
        if (!G.OnDetector)
        {
          continue;
        }
        g = 1.0;
        a = w;
        alpha[0] = G.AlongColumns * P.m_InverseDU;
        alpha[1] = G.AlongRows * P.m_InverseDV;
        alpha[2] = 0.0;
        own.Value += w * G.Value;
      }
      else
      {
        const double depth = P.m_Z0 + P.m_GZ[0] * p[0] + P.m_GZ[1] * p[1] + P.m_GZ[2] * p[2];
        if (!(depth >= P.m_MinimumDepth && depth <= P.m_SID))
        {
          continue; // dropped by the render
        }
        const double inverseZ = 1.0 / depth;
        const double tu = pu * inverseZ, tv = pv * inverseZ;
        column = tu * P.m_SIDOverDU + P.m_ColumnShift;
        const BilinearRead G =
          ReadBilinear(pixelWeights,
                       columns,
                       rows,
                       column,
                       P.m_MagnifiesRows ? tv * P.m_SIDOverDV + P.m_RowShift : pv * P.m_InverseDV + P.m_RowShift);
        if (!G.OnDetector)
        {
          continue;
        }
        // dPhi/dy = a (alpha_u u + alpha_v v + alpha_n n), a = w g / z: the splat's move (grad G^ J_u) and, unbiased,
        // the perspective weight's change (G^ grad g); d depth / dy = -n, d tu / dy = (u + tu n) / z.
        const double gc = G.AlongColumns * P.m_SIDOverDU;
        if (P.m_MagnifiesRows)
        {
          const double s2 = 1.0 + tu * tu + tv * tv;
          const double gr = G.AlongRows * P.m_SIDOverDV;
          g = unbiased ? P.m_SID * P.m_SID * inverseZ * inverseZ * std::sqrt(s2) : 1.0;
          const double h = unbiased ? G.Value : 0.0; // the weight's derivative, or none for the paper's count
          alpha[0] = h * tu / s2 + gc;
          alpha[1] = h * tv / s2 + gr;
          alpha[2] = h * (2.0 + (tu * tu + tv * tv) / s2) + gc * tu + gr * tv;
        }
        else
        {
          // A localizer: a fan across, parallel along the rows (d row / dy = v / dv).
          const double s2 = 1.0 + tu * tu;
          g = unbiased ? P.m_SID * inverseZ * std::sqrt(s2) : 1.0;
          const double h = unbiased ? G.Value : 0.0;
          alpha[0] = h * tu / s2 + gc;
          alpha[1] = G.AlongRows * P.m_InverseDV * depth;
          alpha[2] = h * (1.0 + tu * tu / s2) + gc * tu;
        }
        a = w * g * inverseZ;
        own.Value += w * g * G.Value;
      }
      ++own.OnDetector;
      const double q[3] = { p[0] - p0[0], p[1] - p0[1], p[2] - p0[2] };
      for (unsigned int r = 0; r < 3; ++r)
      {
        const double aa = a * alpha[r];
        own.Alpha[r] += aa;
        own.AlphaIndex[r][0] += aa * q[0];
        own.AlphaIndex[r][1] += aa * q[1];
        own.AlphaIndex[r][2] += aa * q[2];
      }
    }
  };
  DRRWorkScheduler::Run(threader, numberOfChunks, chunk, nullptr);

  // In chunk order: the same bits on any number of threads.
  ChunkSums total;
  for (const ChunkSums & own : sums)
  {
    total.Value += own.Value;
    total.OnDetector += own.OnDetector;
    for (unsigned int r = 0; r < 3; ++r)
    {
      total.Alpha[r] += own.Alpha[r];
      for (unsigned int c = 0; c < 3; ++c)
      {
        total.AlphaIndex[r][c] += own.AlphaIndex[r][c];
      }
    }
  }
  // From the beam's frame to the room: Sum = E alpha, Moment = E (alpha q^T) F^T, E = [u v n], F the index-to-room
  // matrix (y - Reference = F q).
  const VectorType frame[3] = { P.m_U, P.m_V, P.m_Normal };
  for (unsigned int r = 0; r < 3; ++r)
  {
    moments.Sum += frame[r] * total.Alpha[r];
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
          m += frame[r][i] * total.AlphaIndex[r][c] * P.m_IndexToRoom[j][c];
        }
      }
      moments.Moment[i][j] = m;
    }
  }
  moments.Value = total.Value;
  moments.PointsOnDetector = total.OnDetector;
  return moments;
}
} // namespace itk
