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
#include "itkDRRExactRayIntegrator.h"
#include "itkDRRPolicies.h"
#include "itkDRRPhiloxRandom.h"
#include "itkDRRWorkScheduler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace itk
{
DRRExactRayIntegrator::DRRExactRayIntegrator(const DRRAttenuationVolume & volume,
                                             KernelEnum                   kernel,
                                             unsigned int                 indexCoarsening)
  : m_Volume(volume), m_IndexCoarsening(static_cast<double>(indexCoarsening))
{
  // The registry says which exact projector a kernel's model has; this class implements Siddon's and the trilinear one.
  const std::string reference = DRRPolicies::Kernels::Visit(kernel, [](auto policy) {
    return std::string(decltype(policy)::ExactReference ? decltype(policy)::ExactReference : "");
  });
  if (reference != "siddon" && reference != "trilinear")
  {
    itkGenericExceptionMacro("DRRExactRayIntegrator: the " << DRRPolicies::Kernels::GetName(kernel)
                                                           << " kernel has no exact projector");
  }
  m_Siddon = reference == "siddon";
  if (indexCoarsening == 0 || (indexCoarsening > 1 && !m_Siddon))
  {
    itkGenericExceptionMacro("DRRExactRayIntegrator: an index coarsening of "
                             << indexCoarsening << " is not supported (1, or more with the box model)");
  }
  // Box: cells are the voxels, planes at -0.5 .. n - 0.5. Tent: cells lie between the centres of the zero-padded
  // grid, planes at -1 .. n; cell c spans [c - 1, c] and its lower corner is voxel c - 1.
  m_GridStart = m_Siddon ? -0.5 : -1.0;
  for (unsigned int a = 0; a < 3; ++a)
  {
    m_NumberOfCells[a] = static_cast<int64_t>(volume.GetSize()[a]) + (m_Siddon ? 0 : 1);
  }
}

void
DRRExactRayIntegrator::ReadCorners(const MuReaderType & mu,
                                   const int64_t        corner[3],
                                   double               cornerMu[8],
                                   uint64_t             cornerVoxel[8]) const
{
  // mu read through the volume's reader: a volume of keys is looked up in place, with no float copy of the volume
  // (GetMuOrZero() would materialize one). Inside the grid, one test for the cell; at its border, one per corner.
  const int64_t nx = static_cast<int64_t>(m_Volume.GetSize()[0]);
  const int64_t ny = static_cast<int64_t>(m_Volume.GetSize()[1]);
  const int64_t nz = static_cast<int64_t>(m_Volume.GetSize()[2]);
  const int64_t nxy = nx * ny;
  const int64_t offset[8] = { 0, 1, nx, nx + 1, nxy, nxy + 1, nxy + nx, nxy + nx + 1 };
  const int64_t base = corner[0] + nx * corner[1] + nxy * corner[2];
  if (corner[0] >= 0 && corner[1] >= 0 && corner[2] >= 0 && corner[0] + 1 < nx && corner[1] + 1 < ny &&
      corner[2] + 1 < nz)
  {
    for (unsigned int c = 0; c < 8; ++c)
    {
      cornerVoxel[c] = static_cast<uint64_t>(base + offset[c]);
      cornerMu[c] = mu(cornerVoxel[c]);
    }
    return;
  }
  for (unsigned int c = 0; c < 8; ++c)
  {
    const int64_t i = corner[0] + (c & 1u);
    const int64_t j = corner[1] + ((c >> 1) & 1u);
    const int64_t k = corner[2] + ((c >> 2) & 1u);
    const bool    inside = i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz;
    cornerVoxel[c] = inside ? static_cast<uint64_t>(base + offset[c]) : 0;
    cornerMu[c] = inside ? static_cast<double>(mu(cornerVoxel[c])) : 0.0; // the zero padding
  }
}

double
DRRExactRayIntegrator::Trilinear(const double   cornerMu[8],
                                 const uint64_t cornerVoxel[8],
                                 const double   fraction[3],
                                 double *       channels,
                                 double         channelScale) const
{
  // Corner c's weight is (wx wy) wz, the products of the general formula in its order, with each wx wy made once for
  // the two corners that share it. A corner in the padding adds w 0 = +0 (w >= 0: the fractions are clamped to
  // [0, 1]), which leaves the sum's bits as they are, and its term is never a channel's. Without channels the loop
  // tests nothing: the test of a term against zero, interleaved with the sum, was a branch on air or tissue that the
  // predictor missed at every boundary (half the time of the trilinear render on the chest).
  const double wx[2] = { 1.0 - fraction[0], fraction[0] };
  const double wy[2] = { 1.0 - fraction[1], fraction[1] };
  const double wz[2] = { 1.0 - fraction[2], fraction[2] };
  const double wxy[4] = { wx[0] * wy[0], wx[1] * wy[0], wx[0] * wy[1], wx[1] * wy[1] };
  double       value = 0.0;
  if (!channels)
  {
    for (unsigned int c = 0; c < 8; ++c)
    {
      value += wxy[c & 3u] * wz[c >> 2] * cornerMu[c];
    }
    return value;
  }
  for (unsigned int c = 0; c < 8; ++c)
  {
    const double term = wxy[c & 3u] * wz[c >> 2] * cornerMu[c];
    value += term;
    if (term != 0.0)
    {
      channels[m_Volume.GetVoxelChannels()[cornerVoxel[c]]] += channelScale * term;
    }
  }
  return value;
}

template <bool VChannels, unsigned int VDominant>
double
DRRExactRayIntegrator::TraverseBox(MuReaderType  mu,
                                   const int64_t cell[3],
                                   const int64_t step[3],
                                   const double  tNext[3],
                                   const double  tDelta[3],
                                   double        tEnter,
                                   double        tExit,
                                   double *      channels,
                                   double        channelScale) const
{
  // The traversal of IntegrateSegment(), specialised for the box model: the voxel's offset is updated by a stride,
  // and each axis counts the planes left before the grid's end instead of testing the cell against both bounds. The
  // cursors are indexed by constants only, so they live in registers (an array indexed by a variable axis goes
  // through memory at every step). The axis is chosen by the general loop's rule, the first plane with ties to the
  // larger axis, written as a test of the dominant axis (the one of most planes, VDominant) first: most steps cross
  // its planes, and they run straight through one short path, where the general selection jumped two or three times
  // per step. The same operations in the same order on the same values: the same bits as the general loop. The
  // reader is taken by value, a local whose pointers stay in registers rather than being read again at every step.
  constexpr unsigned int D = VDominant;
  constexpr unsigned int A = (D + 1) % 3;
  constexpr unsigned int B = (D + 2) % 3;
  const int64_t          nx = static_cast<int64_t>(m_Volume.GetSize()[0]);
  const int64_t          nxy = nx * static_cast<int64_t>(m_Volume.GetSize()[1]);
  const uint8_t *        voxelChannels = m_Volume.GetVoxelChannels();
  int64_t       voxel = cell[0] + nx * cell[1] + nxy * cell[2]; // the last step may leave the grid: never read then
  const int64_t stride[3] = { step[0], step[1] * nx, step[2] * nxy };
  // Planes left along each axis before the ray leaves the grid (an axis the ray does not cross is never chosen).
  int64_t left[3];
  double  next[3];
  for (unsigned int a = 0; a < 3; ++a)
  {
    left[a] = step[a] > 0 ? m_NumberOfCells[a] - cell[a] : cell[a] + 1;
    next[a] = tNext[a];
  }
  const double delta[3] = { tDelta[0], tDelta[1], tDelta[2] };
  double       integral = 0.0;
  double       t = tEnter;
  // Whether axis a's plane comes before axis b's: the earlier one, or on a tie the larger axis.
  const auto before = [&next](auto a, auto b) {
    return decltype(a)::value > decltype(b)::value ? next[decltype(a)::value] <= next[decltype(b)::value]
                                                   : next[decltype(a)::value] < next[decltype(b)::value];
  };
  // The segment up to axis a's plane (or the exit), then the step across it; false once the ray leaves the grid.
  const auto advance = [&](auto axis) {
    constexpr unsigned int a = decltype(axis)::value;
    const double           tEnd = std::min(next[a], tExit);
    if (tEnd > t)
    {
      integral += (tEnd - t) * mu(static_cast<uint64_t>(voxel));
      if (VChannels)
      {
        channels[voxelChannels[voxel]] += channelScale * ((tEnd - t) * mu(static_cast<uint64_t>(voxel)));
      }
    }
    t = tEnd;
    next[a] += delta[a];
    voxel += stride[a];
    return --left[a] != 0;
  };
  using DAxis = std::integral_constant<unsigned int, D>;
  using AAxis = std::integral_constant<unsigned int, A>;
  using BAxis = std::integral_constant<unsigned int, B>;
  while (t < tExit)
  {
    if (before(DAxis(), AAxis()) && before(DAxis(), BAxis()))
    {
      if (!advance(DAxis()))
      {
        break;
      }
    }
    else if (!(before(AAxis(), BAxis()) ? advance(AAxis()) : advance(BAxis())))
    {
      break;
    }
  }
  return integral;
}

bool
DRRExactRayIntegrator::ClipToGrid(const double p0[3], const double p1[3], double d[3], double & tEnter, double & tExit)
  const
{
  for (unsigned int a = 0; a < 3; ++a)
  {
    d[a] = p1[a] - p0[a];
    const double low = m_GridStart;
    const double high = m_GridStart + static_cast<double>(m_NumberOfCells[a]);
    if (d[a] == 0.0)
    {
      if (p0[a] <= low || p0[a] >= high)
      {
        return false;
      }
      continue;
    }
    const double t1 = (low - p0[a]) / d[a];
    const double t2 = (high - p0[a]) / d[a];
    tEnter = std::max(tEnter, std::min(t1, t2));
    tExit = std::min(tExit, std::max(t1, t2));
  }
  return tEnter < tExit;
}

double
DRRExactRayIntegrator::CountCrossedCells(const DRRPointProjection & projection, double column, double row) const
{
  double p0[3];
  double p1[3];
  this->ComputeRaySegment(projection, column, row, p0, p1);
  double d[3];
  double tEnter = 0.0;
  double tExit = 1.0;
  if (!this->ClipToGrid(p0, p1, d, tEnter, tExit))
  {
    return 0.0;
  }
  // Each plane crossed starts a cell: the planes of an axis a segment crosses are its extent along the axis.
  double cells = 1.0;
  for (unsigned int a = 0; a < 3; ++a)
  {
    cells += std::abs(d[a]) * (tExit - tEnter);
  }
  return cells;
}

void
DRRExactRayIntegrator::StartTraversal(const double p0[3],
                                      const double d[3],
                                      double       tEnter,
                                      int64_t      cell[3],
                                      int64_t      step[3],
                                      double       tNext[3],
                                      double       tDelta[3]) const
{
  for (unsigned int a = 0; a < 3; ++a)
  {
    const double position = p0[a] + tEnter * d[a] - m_GridStart;
    double       base = std::floor(position);
    if (position == base && d[a] < 0.0)
    {
      base -= 1.0; // on a plane and moving down: the cell below
    }
    cell[a] = std::min<int64_t>(std::max<int64_t>(static_cast<int64_t>(base), 0), m_NumberOfCells[a] - 1);
    if (d[a] > 0.0)
    {
      step[a] = 1;
      tNext[a] = (m_GridStart + static_cast<double>(cell[a] + 1) - p0[a]) / d[a];
      tDelta[a] = 1.0 / d[a];
    }
    else if (d[a] < 0.0)
    {
      step[a] = -1;
      tNext[a] = (m_GridStart + static_cast<double>(cell[a]) - p0[a]) / d[a];
      tDelta[a] = -1.0 / d[a];
    }
    else
    {
      step[a] = 0;
      tNext[a] = std::numeric_limits<double>::infinity();
      tDelta[a] = std::numeric_limits<double>::infinity();
    }
  }
}

std::vector<uint64_t>
DRRExactRayIntegrator::ListReadCacheLines(const DRRPointProjection & projection, double column, double row) const
{
  std::vector<uint64_t> lines;
  double                p0[3];
  double                p1[3];
  this->ComputeRaySegment(projection, column, row, p0, p1);
  double d[3];
  double tEnter = 0.0;
  double tExit = 1.0;
  if (!this->ClipToGrid(p0, p1, d, tEnter, tExit))
  {
    return lines;
  }
  int64_t cell[3];
  int64_t step[3];
  double  tNext[3];
  double  tDelta[3];
  this->StartTraversal(p0, d, tEnter, cell, step, tNext, tDelta);
  const uint64_t nx = m_Volume.GetSize()[0];
  const uint64_t nxy = nx * m_Volume.GetSize()[1];
  const uint64_t bytes = m_Volume.GetMuReader().GetBytesPerVoxel();
  // The cell's voxel (the trilinear grid's cell: its lower corner, the padding clamped into the volume).
  const auto voxelLine = [&]() {
    uint64_t index[3];
    for (unsigned int a = 0; a < 3; ++a)
    {
      index[a] = static_cast<uint64_t>(
        std::min<int64_t>(std::max<int64_t>(cell[a], 0), static_cast<int64_t>(m_Volume.GetSize()[a]) - 1));
    }
    return (index[0] + nx * index[1] + nxy * index[2]) * bytes / CacheLineBytes;
  };
  double t = tEnter;
  while (t < tExit)
  {
    const uint64_t line = voxelLine();
    if (lines.empty() || lines.back() != line)
    {
      lines.push_back(line);
    }
    const unsigned int a = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
    t = tNext[a];
    tNext[a] += tDelta[a];
    cell[a] += step[a];
    if (cell[a] < 0 || cell[a] >= m_NumberOfCells[a])
    {
      break;
    }
  }
  return lines;
}

double
DRRExactRayIntegrator::IntegrateSegment(const double p0[3],
                                        const double p1[3],
                                        double *     channels,
                                        double       channelScale) const
{
  if (channels && !m_Volume.GetVoxelChannels())
  {
    itkGenericExceptionMacro("DRRExactRayIntegrator: channel integrals asked of a volume without channels");
  }
  double d[3];
  double tEnter = 0.0;
  double tExit = 1.0;
  if (!this->ClipToGrid(p0, p1, d, tEnter, tExit))
  {
    return 0.0;
  }

  int64_t cell[3];
  int64_t step[3];
  double  tNext[3];
  double  tDelta[3];
  this->StartTraversal(p0, d, tEnter, cell, step, tNext, tDelta);

  // mu read in place from a volume of keys (16-bit input adds no byte per voxel), else from mu per voxel.
  const MuReaderType mu = m_Volume.GetMuReader();
  if (m_Siddon)
  {
    // The dominant axis: the most planes, the smallest parameter between two (an axis not crossed has infinity).
    const unsigned int dominant =
      tDelta[0] < tDelta[1] ? (tDelta[0] < tDelta[2] ? 0 : 2) : (tDelta[1] < tDelta[2] ? 1 : 2);
    switch (dominant)
    {
      case 0:
        return channels
                 ? this->TraverseBox<true, 0>(mu, cell, step, tNext, tDelta, tEnter, tExit, channels, channelScale)
                 : this->TraverseBox<false, 0>(mu, cell, step, tNext, tDelta, tEnter, tExit, nullptr, 0.0);
      case 1:
        return channels
                 ? this->TraverseBox<true, 1>(mu, cell, step, tNext, tDelta, tEnter, tExit, channels, channelScale)
                 : this->TraverseBox<false, 1>(mu, cell, step, tNext, tDelta, tEnter, tExit, nullptr, 0.0);
      default:
        return channels
                 ? this->TraverseBox<true, 2>(mu, cell, step, tNext, tDelta, tEnter, tExit, channels, channelScale)
                 : this->TraverseBox<false, 2>(mu, cell, step, tNext, tDelta, tEnter, tExit, nullptr, 0.0);
    }
  }
  const double gaussOffset = 0.5 / std::sqrt(3.0);
  double       integral = 0.0;
  double       t = tEnter;
  while (t < tExit)
  {
    const unsigned int axis = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
    const double       tEnd = std::min(tNext[axis], tExit);
    if (tEnd > t)
    {
      const int64_t corner[3] = { cell[0] - 1, cell[1] - 1, cell[2] - 1 };
      // The two nodes interpolate the same corners: read once.
      double   cornerMu[8];
      uint64_t cornerVoxel[8];
      this->ReadCorners(mu, corner, cornerMu, cornerVoxel);
      const double length = tEnd - t;
      const double middle = 0.5 * (t + tEnd);
      for (double node : { middle - gaussOffset * length, middle + gaussOffset * length })
      {
        // The node lies in this cell, but its position, rounded apart from the traversal's, can fall outside the
        // cell by a few ulps (a ray on a plane of the dual grid: through voxel centres): a fraction of -1e-16 gives
        // a negative weight, and a neighbour of mu 1e25 /mm a negative integral. Clamped to the cell, the weights
        // stay a convex combination of the corners' mu, so the integrand is never negative; the ray moves by
        // rounding only, and a fraction within [0, 1] is unchanged.
        double fraction[3];
        for (unsigned int a = 0; a < 3; ++a)
        {
          fraction[a] = std::min(std::max(p0[a] + node * d[a] - static_cast<double>(corner[a]), 0.0), 1.0);
        }
        integral +=
          0.5 * length * this->Trilinear(cornerMu, cornerVoxel, fraction, channels, channelScale * 0.5 * length);
      }
    }
    t = tEnd;
    cell[axis] += step[axis];
    tNext[axis] += tDelta[axis];
    if (cell[axis] < 0 || cell[axis] >= m_NumberOfCells[axis])
    {
      break;
    }
  }
  return integral;
}

double
DRRExactRayIntegrator::ComputeRaySegment(const DRRPointProjection & projection,
                                         double                     column,
                                         double                     row,
                                         double                     p0[3],
                                         double                     p1[3]) const
{
  using PointType = DRRPointProjection::PointType;
  const PointType pixel = projection.GetPixelPosition(column, row);
  PointType       start;
  PointType       end;
  if (projection.IsPerspective())
  {
    // A localizer's source moves with the table, along the rows' direction, to the pixel's row.
    start = projection.GetSource();
    if (!projection.MagnifiesRows())
    {
      start += projection.GetRowDirection() * ((pixel - start) * projection.GetRowDirection());
    }
    end = pixel;
  }
  else
  {
    // The whole line through the pixel along n: clip it to the depth range of the model's support box.
    double sMin = std::numeric_limits<double>::infinity();
    double sMax = -sMin;
    for (unsigned int corner = 0; corner < 8; ++corner)
    {
      double p[3];
      for (unsigned int a = 0; a < 3; ++a)
      {
        const double own =
          (corner >> a) & 1u ? m_GridStart + static_cast<double>(m_NumberOfCells[a]) + 1.0 : m_GridStart - 1.0;
        p[a] = m_IndexCoarsening * (own + 0.5) - 0.5;
      }
      const double s = (projection.IndexToRoom(p) - pixel) * projection.GetNormal();
      sMin = std::min(sMin, s);
      sMax = std::max(sMax, s);
    }
    start = pixel + projection.GetNormal() * sMax;
    end = pixel + projection.GetNormal() * sMin;
  }
  projection.RoomToIndex(start, p0);
  projection.RoomToIndex(end, p1);
  if (m_IndexCoarsening != 1.0)
  {
    for (unsigned int a = 0; a < 3; ++a)
    {
      p0[a] = (p0[a] + 0.5) / m_IndexCoarsening - 0.5;
      p1[a] = (p1[a] + 0.5) / m_IndexCoarsening - 0.5;
    }
  }
  return (end - start).GetNorm();
}

double
DRRExactRayIntegrator::IntegrateRay(const DRRPointProjection & projection,
                                    double                     column,
                                    double                     row,
                                    double *                   channels) const
{
  double       p0[3];
  double       p1[3];
  const double length = this->ComputeRaySegment(projection, column, row, p0, p1);
  return length * this->IntegrateSegment(p0, p1, channels, length);
}

std::vector<double>
DRRExactRayIntegrator::RenderProjection(const DRRPointProjection & projection,
                                        unsigned int               raysPerSide,
                                        MultiThreaderBase *        threader,
                                        ProcessObject *            progressFilter,
                                        std::vector<double> *      channelImage) const
{
  if (raysPerSide == 0)
  {
    itkGenericExceptionMacro("DRRExactRayIntegrator: the number of rays per pixel side must be at least 1");
  }
  const unsigned int  columns = projection.GetNumberOfColumns();
  const unsigned int  rows = projection.GetNumberOfRows();
  std::vector<double> image(static_cast<size_t>(columns) * rows, 0.0);
  const size_t        K = m_Volume.GetVoxelChannels() && channelImage ? m_Volume.GetNumberOfChannels() : 0;
  if (channelImage)
  {
    channelImage->assign(image.size() * K, 0.0);
  }
  const double inverseRays = 1.0 / static_cast<double>(raysPerSide);
  const double inverseRayCount = inverseRays * inverseRays;
  // Work items of up to 64 pixels of a row, not whole rows: the scheduler's waves end when their last item does, and
  // rows differ in cost (those past the volume's ends are nearly free), so whole rows (5 per wave for 256 rows on
  // 2 threads) left a thread idle at the end of most waves. 64 neighbouring rays still share most of the volume's
  // cache lines they read (16 columns did not: more time per ray). A pixel is computed alone: the same bits.
  constexpr unsigned int tileColumns = 64;
  const unsigned int     tilesPerRow = (columns + tileColumns - 1) / tileColumns;
  DRRWorkScheduler::Run(
    threader,
    static_cast<uint64_t>(rows) * tilesPerRow,
    [&](unsigned int, uint64_t tile) {
      const uint64_t     row = tile / tilesPerRow;
      const unsigned int first = static_cast<unsigned int>(tile % tilesPerRow) * tileColumns;
      for (unsigned int column = first; column < std::min(columns, first + tileColumns); ++column)
      {
        const size_t pixel = static_cast<size_t>(row) * columns + column;
        double *     channels = K > 0 ? channelImage->data() + pixel * K : nullptr;
        double       sum = 0.0;
        for (unsigned int sv = 0; sv < raysPerSide; ++sv)
        {
          const double r = static_cast<double>(row) + (sv + 0.5) * inverseRays - 0.5;
          for (unsigned int su = 0; su < raysPerSide; ++su)
          {
            const double c = static_cast<double>(column) + (su + 0.5) * inverseRays - 0.5;
            sum += this->IntegrateRay(projection, c, r, channels);
          }
        }
        image[pixel] = sum * inverseRayCount;
        for (size_t k = 0; k < K; ++k)
        {
          channels[k] *= inverseRayCount;
        }
      }
    },
    progressFilter);
  return image;
}

void
DRRExactRayIntegrator::RenderFootprintAverages(const DRRPointProjection & projection,
                                               SplatEnum                  splat,
                                               unsigned int               raysPerSide,
                                               uint64_t                   seed,
                                               MultiThreaderBase *        threader,
                                               ProcessObject *            progressFilter,
                                               std::vector<double> &      image,
                                               std::vector<double> &      standardError,
                                               unsigned int               replicates) const
{
  if (raysPerSide == 0)
  {
    itkGenericExceptionMacro("DRRExactRayIntegrator: the number of rays per pixel side must be at least 1");
  }
  if (replicates != 1 && replicates != 2)
  {
    itkGenericExceptionMacro("DRRExactRayIntegrator: replicates must be 1 or 2, got " << replicates);
  }
  const unsigned int columns = projection.GetNumberOfColumns();
  const unsigned int rows = projection.GetNumberOfRows();
  image.assign(static_cast<size_t>(columns) * rows, 0.0);
  standardError.assign(image.size(), 0.0);
  const double raysPerReplicate = 2.0 * raysPerSide * raysPerSide; // antithetic pairs
  const double inverseRays = 1.0 / static_cast<double>(raysPerSide);
  DRRPolicies::Splats::Visit(splat, [&](auto policy) {
    using SplatType = decltype(policy);
    DRRWorkScheduler::Run(
      threader,
      rows,
      [&](unsigned int, uint64_t row) {
        // Stream 2 of the row (the point renders use streams 0 and 1 of their chunks): the same rays on any threads.
        detail::DRRPhiloxRandom stream(seed, row, 2);
        for (unsigned int column = 0; column < columns; ++column)
        {
          double replicate[2] = { 0.0, 0.0 };
          for (unsigned int r = 0; r < replicates; ++r)
          {
            double & mean = replicate[r];
            double   sum = 0.0;
            for (unsigned int sv = 0; sv < raysPerSide; ++sv)
            {
              for (unsigned int su = 0; su < raysPerSide; ++su)
              {
                // An antithetic pair: the ray jittered in its stratum and its mirror through the stratum's centre.
                // Each is distributed as the footprint (FootprintOffset maps uniform to it), so their mean is
                // unbiased; the mirror cancels the linear part of L across the stratum, which dominates the spread of
                // a lone jittered ray (DESIGN 10; docs/design.md, "the coarse image").
                const detail::DRRPhiloxRandom::BlockType bits = stream.Next();
                const double                             ju = detail::DRRPhiloxRandom::ToUnitInterval(bits[0]);
                const double                             jv = detail::DRRPhiloxRandom::ToUnitInterval(bits[1]);
                sum +=
                  this->IntegrateRay(projection,
                                     static_cast<double>(column) + SplatType::FootprintOffset((su + ju) * inverseRays),
                                     static_cast<double>(row) + SplatType::FootprintOffset((sv + jv) * inverseRays));
                sum += this->IntegrateRay(
                  projection,
                  static_cast<double>(column) + SplatType::FootprintOffset((su + 1.0 - ju) * inverseRays),
                  static_cast<double>(row) + SplatType::FootprintOffset((sv + 1.0 - jv) * inverseRays));
              }
            }
            mean = sum / raysPerReplicate;
          }
          const size_t pixel = static_cast<size_t>(row) * columns + column;
          // The first replicate is the same rays either way (the row's stream is drawn in order).
          image[pixel] = replicates == 2 ? 0.5 * (replicate[0] + replicate[1]) : replicate[0];
          standardError[pixel] = replicates == 2 ? 0.5 * std::abs(replicate[0] - replicate[1]) : 0.0;
        }
      },
      progressFilter);
    return 0;
  });
}
} // namespace itk
