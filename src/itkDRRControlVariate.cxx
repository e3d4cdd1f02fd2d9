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
#include "itkDRRControlVariate.h"
#include "itkDRRCompilerBuiltins.h"
#include "itkDRRExactRayIntegrator.h"
#include "itkDRRSubtractCoarseRow.h"

#include <algorithm>
#include <cmath>

namespace itk
{
namespace
{
/** sum[q] += the row's voxels q F .. q F + F - 1 (fewer in a last, partial block), each block's in order. */
template <uint64_t TFactor>
void
AddWholeBlockSums(const float * row, uint64_t blocks, double * sum)
{
  for (uint64_t q = 0; q < blocks; ++q)
  {
    double s = sum[q];
    for (uint64_t t = 0; t < TFactor; ++t)
    {
      s += row[TFactor * q + t];
    }
    sum[q] = s;
  }
}

PointBasedDRR_VECTOR_CLONES void
AddBlockSums(const float * PointBasedDRR_RESTRICT row,
             uint64_t                             width,
             uint64_t                             factor,
             double * PointBasedDRR_RESTRICT      sum)
{
  // The usual factors in loops of fixed length; the last block, and other factors, voxel by voxel.
  uint64_t whole = width / factor;
  switch (factor)
  {
    case 2:
      AddWholeBlockSums<2>(row, whole, sum);
      break;
    case 4:
      AddWholeBlockSums<4>(row, whole, sum);
      break;
    case 8:
      AddWholeBlockSums<8>(row, whole, sum);
      break;
    case 16:
      AddWholeBlockSums<16>(row, whole, sum);
      break;
    default:
      whole = 0;
      break;
  }
  for (uint64_t q = whole; q * factor < width; ++q)
  {
    for (uint64_t i = q * factor; i < std::min(width, q * factor + factor); ++i)
    {
      sum[q] += row[i];
    }
  }
}

/** 1 / F^3: a block's mean from its sum (the padding's air counts in the F^3 voxels). */
double
InverseBlockVolume(uint64_t factor)
{
  return 1.0 / (static_cast<double>(factor) * static_cast<double>(factor) * static_cast<double>(factor));
}

/** means[q] for the `blocks` blocks of the coarse row (cj, ck) from its fine rows: each block's voxels summed k, then
 * j, then i, in double, over the rows inside the fine grid (air pads the last blocks), divided by F^3. rowOf(j, k)
 * gives the fine row (j, k) from the first block's first voxel on, `width` voxels (fewer than blocks F where the
 * grid ends); sum is room for the blocks' sums. The one account of a block's sum: the coarse volume built alone and in
 * the sets of rows of a sampler's tables give the same bits through it. */
template <typename TRowOf>
void
MeansOfBlockRow(TRowOf &&                              rowOf,
                uint64_t                               factor,
                uint64_t                               cj,
                uint64_t                               ck,
                const DRRAttenuationVolume::SizeType & fine,
                uint64_t                               width,
                uint64_t                               blocks,
                std::vector<double> &                  sum,
                float *                                means)
{
  const uint64_t F = factor;
  sum.assign(blocks, 0.0);
  for (uint64_t k = ck * F; k < std::min(fine[2], ck * F + F); ++k)
  {
    for (uint64_t j = cj * F; j < std::min(fine[1], cj * F + F); ++j)
    {
      AddBlockSums(rowOf(j, k), width, F, sum.data());
    }
  }
  const double inverseBlockVolume = InverseBlockVolume(F);
  for (uint64_t q = 0; q < blocks; ++q)
  {
    means[q] = static_cast<float>(sum[q] * inverseBlockVolume);
  }
}

/** means[q] = (the F^2 rows' voxels F q .. F q + F - 1 summed row by row, in double) / F^3 for q < blocks: the block
 * means of one coarse row from its fine rows, each block's sum in the order AddBlockSums() adds them, kept in a
 * register instead of an array of sums. */
template <uint64_t TFactor>
inline void
MeansOfWholeBlocks(const float * const * rows, uint64_t blocks, double inverseBlockVolume, float * means)
{
  for (uint64_t q = 0; q < blocks; ++q)
  {
    double s = 0.0;
    for (uint64_t r = 0; r < TFactor * TFactor; ++r)
    {
      for (uint64_t t = 0; t < TFactor; ++t)
      {
        s += rows[r][TFactor * q + t];
      }
    }
    means[q] = static_cast<float>(s * inverseBlockVolume);
  }
}

/** MeansOfWholeBlocks() for F 2 and 4 (the blocks of a row of the padded grid), in the CPU's widest vectors. */
PointBasedDRR_VECTOR_CLONES void
MeansOfSmallBlocks(const float * const *          rows,
                   uint64_t                       factor,
                   uint64_t                       blocks,
                   double                         inverseBlockVolume,
                   float * PointBasedDRR_RESTRICT means)
{
  if (factor == 2)
  {
    MeansOfWholeBlocks<2>(rows, blocks, inverseBlockVolume, means);
  }
  else
  {
    MeansOfWholeBlocks<4>(rows, blocks, inverseBlockVolume, means);
  }
}

/** The sets of side x side rows that cover a grid's rows. */
uint64_t
CountSetsOfRows(uint64_t side, const DRRAttenuationVolume::SizeType & grid)
{
  return ((grid[1] + side - 1) / side) * ((grid[2] + side - 1) / side);
}

/** Where set `set` of side x side rows lies in a grid (sets numbered along y first, then z; the last ones clipped to
 * the grid), with no rows yet. */
DRRControlVariate::ResidualRows
SetOfRows(uint64_t set, uint64_t side, const DRRAttenuationVolume::SizeType & grid)
{
  const uint64_t                  setsAlongY = (grid[1] + side - 1) / side;
  DRRControlVariate::ResidualRows rows;
  rows.FirstRow = set % setsAlongY * side;
  rows.FirstPlane = set / setsAlongY * side;
  rows.NumberOfRows = std::min(side, grid[1] - rows.FirstRow);
  rows.NumberOfPlanes = std::min(side, grid[2] - rows.FirstPlane);
  rows.Width = grid[0];
  rows.Mu = nullptr;
  return rows;
}
} // namespace

DRRControlVariate::DRRControlVariate()
  : m_CoarseVolume(DRRAttenuationVolume::New()), m_ResidualVolume(DRRAttenuationVolume::New())
{}

void
DRRControlVariate::Build(const DRRAttenuationVolume & volume, unsigned int factor, MultiThreaderBase * threader)
{
  this->Build(volume, factor, threader, ResidualRowsFunctionType());
}

void
DRRControlVariate::VerifyFactor(unsigned int factor)
{
  if (factor < 2 || factor > MaximumFactor)
  {
    itkGenericExceptionMacro("DRRControlVariate: the coarsening factor must be 2 to " << MaximumFactor << ", not "
                                                                                      << factor);
  }
}

DRRAttenuationVolume::SizeType
DRRControlVariate::ComputeResidualSize(const DRRAttenuationVolume::SizeType & size, unsigned int factor)
{
  VerifyFactor(factor);
  DRRAttenuationVolume::SizeType residual;
  for (unsigned int a = 0; a < 3; ++a)
  {
    residual[a] = (size[a] + factor - 1) / factor * factor;
  }
  return residual;
}

void
DRRControlVariate::Build(const DRRAttenuationVolume &     volume,
                         unsigned int                     factor,
                         MultiThreaderBase *              threader,
                         const ResidualRowsFunctionType & visit)
{
  VerifyFactor(factor);
  for (unsigned int a = 0; a < 3; ++a)
  {
    if (volume.GetSize()[a] == 0)
    {
      itkExceptionMacro("the control variate needs a volume with at least one voxel");
    }
  }
  m_Factor = factor;
  m_TotalMass = volume.ComputeTotalMass();
  const bool inSetsOfRows = visit && (factor == 2 || factor == 4 || factor == 8 || factor == 16);
  if (inSetsOfRows)
  {
    this->BuildInSetsOfRows(volume, threader, visit);
  }
  else
  {
    this->BuildCoarseVolume(volume, threader);
  }
  // No pass: |r| and its sign are computed where they are read (the sampler's walk, the renderer's points).
  m_ResidualVolume->BuildResidual(volume, *m_CoarseVolume, m_Factor);
  if (visit && !inSetsOfRows)
  {
    this->VisitResidualRows(threader, visit);
  }
  this->Modified();
}

void
DRRControlVariate::BuildInSetsOfRows(const DRRAttenuationVolume &     volume,
                                     MultiThreaderBase *              threader,
                                     const ResidualRowsFunctionType & visit)
{
  const uint64_t                       F = m_Factor;
  const DRRAttenuationVolume::SizeType fine = volume.GetSize();
  const DRRAttenuationVolume::SizeType padded = ComputeResidualSize(fine, m_Factor);
  DRRAttenuationVolume::SizeType       coarse;
  for (unsigned int a = 0; a < 3; ++a)
  {
    coarse[a] = padded[a] / F;
  }
  // Sets of side x side rows, side a multiple of F and of the bricks' 8: each holds whole blocks and whole bricks.
  const uint64_t           side = std::max<uint64_t>(8, F);
  const uint64_t           numberOfSets = CountSetsOfRows(side, padded);
  const double             inverseBlockVolume = InverseBlockVolume(F);
  std::unique_ptr<float[]> coarseMu(new float[coarse[0] * coarse[1] * coarse[2]]);
  float *                  coarseOut = coarseMu.get();
  DRRAttenuationVolume::ParallelizeBlocksPerWorker(
    numberOfSets,
    [&]() -> DRRAttenuationVolume::BlockFunctionType {
      // The worker's own rows and sums, reused from set to set.
      auto rows = std::make_shared<std::vector<float>>(side * side * padded[0]);
      auto sum = std::make_shared<std::vector<double>>(coarse[0]);
      return [&, rows, sum](uint64_t set) {
        ResidualRows residual = SetOfRows(set, side, padded);
        const auto   row = [&](uint64_t j, uint64_t k) {
          return rows->data() + padded[0] * (j - residual.FirstRow + residual.NumberOfRows * (k - residual.FirstPlane));
        };
        // The volume's rows, air in the padding (as the residual volume reads them, FillMuRowSlow()).
        for (uint64_t k = residual.FirstPlane; k < residual.FirstPlane + residual.NumberOfPlanes; ++k)
        {
          for (uint64_t j = residual.FirstRow; j < residual.FirstRow + residual.NumberOfRows; ++j)
          {
            float *        out = row(j, k);
            const uint64_t inside = j < fine[1] && k < fine[2] ? fine[0] : 0;
            if (inside > 0)
            {
              // The rows of a set are 8 (or 16) short runs of memory, one per plane, too short for the hardware to
              // see a stream: ask for the row one plane on while this one is read (12% faster on the chest).
              if (k + 1 < std::min(fine[2], residual.FirstPlane + residual.NumberOfPlanes))
              {
                volume.PrefetchBox(0, j, k + 1, inside, 1, 1);
              }
              volume.FillMuRow(0, j, k, inside, out);
            }
            std::fill(out + inside, out + padded[0], 0.0f);
          }
        }
        // The blocks' means, each block's voxels summed k, then j, then i, as BuildCoarseVolume() sums them.
        for (uint64_t ck = residual.FirstPlane / F; ck < (residual.FirstPlane + residual.NumberOfPlanes) / F; ++ck)
        {
          for (uint64_t cj = residual.FirstRow / F; cj < (residual.FirstRow + residual.NumberOfRows) / F; ++cj)
          {
            float * means = coarseOut + coarse[0] * (cj + coarse[1] * ck);
            if (F <= 4)
            {
              // Small blocks: all F^2 rows at once (air in the padding's rows adds +0, which changes no sum).
              const float * blockRows[16];
              for (uint64_t r = 0; r < F * F; ++r)
              {
                blockRows[r] = row(cj * F + r % F, ck * F + r / F);
              }
              MeansOfSmallBlocks(blockRows, F, coarse[0], inverseBlockVolume, means);
              continue;
            }
            MeansOfBlockRow(row, F, cj, ck, fine, fine[0], coarse[0], *sum, means);
          }
        }
        // |mu - mu_c| in place, as the residual volume computes its rows.
        for (uint64_t k = residual.FirstPlane; k < residual.FirstPlane + residual.NumberOfPlanes; ++k)
        {
          for (uint64_t j = residual.FirstRow; j < residual.FirstRow + residual.NumberOfRows; ++j)
          {
            detail::SubtractCoarseRow(
              coarseOut + coarse[0] * (j / F + coarse[1] * (k / F)), F, 0, 0, padded[0], row(j, k));
          }
        }
        residual.Mu = rows->data();
        visit(residual);
      };
    },
    threader);
  m_CoarseVolume->BuildFromMu(coarse, std::move(coarseMu), threader);
  this->SetCoarseGrid(volume);
}

void
DRRControlVariate::VisitResidualRows(MultiThreaderBase * threader, const ResidualRowsFunctionType & visit) const
{
  const DRRAttenuationVolume &         residualVolume = *m_ResidualVolume;
  const DRRAttenuationVolume::SizeType size = residualVolume.GetSize();
  constexpr uint64_t                   side = 8;
  DRRAttenuationVolume::ParallelizeBlocksPerWorker(
    CountSetsOfRows(side, size),
    [&]() -> DRRAttenuationVolume::BlockFunctionType {
      auto rows = std::make_shared<std::vector<float>>(side * side * size[0]);
      return [&, rows](uint64_t set) {
        ResidualRows residual = SetOfRows(set, side, size);
        residual.Mu = rows->data();
        for (uint64_t z = 0; z < residual.NumberOfPlanes; ++z)
        {
          for (uint64_t y = 0; y < residual.NumberOfRows; ++y)
          {
            residualVolume.FillMuRow(0,
                                     residual.FirstRow + y,
                                     residual.FirstPlane + z,
                                     size[0],
                                     rows->data() + size[0] * (y + residual.NumberOfRows * z));
          }
        }
        visit(residual);
      };
    },
    threader);
}

void
DRRControlVariate::BuildCoarseVolume(const DRRAttenuationVolume & volume, MultiThreaderBase * threader)
{
  const uint64_t                       F = m_Factor;
  const DRRAttenuationVolume::SizeType fine = volume.GetSize();
  DRRAttenuationVolume::SizeType       coarse;
  for (unsigned int a = 0; a < 3; ++a)
  {
    coarse[a] = (fine[a] + F - 1) / F;
  }
  // The fine rows are read once per coarse row (MeansOfBlockRow()).
  m_CoarseVolume->BuildFromMu(
    coarse,
    [&](uint64_t begin, uint64_t end, float * coarseMu) {
      std::vector<float>  row;
      std::vector<double> sum;
      for (uint64_t c = begin; c < end;)
      {
        const uint64_t ci = c % coarse[0];
        const uint64_t cj = (c / coarse[0]) % coarse[1];
        const uint64_t ck = c / (coarse[0] * coarse[1]);
        const uint64_t n = std::min(end - c, coarse[0] - ci); // blocks of this coarse row in the range
        const uint64_t first = ci * F;
        const uint64_t width = std::min(fine[0], (ci + n) * F) - first;
        row.resize(width);
        const auto fineRow = [&](uint64_t j, uint64_t k) {
          volume.FillMuRow(first, j, k, width, row.data());
          return row.data();
        };
        MeansOfBlockRow(fineRow, F, cj, ck, fine, width, n, sum, coarseMu + c);
        c += n;
      }
    },
    threader);
  this->SetCoarseGrid(volume);
}

void
DRRControlVariate::SetCoarseGrid(const DRRAttenuationVolume & volume)
{
  // Coarse voxel c is the box of fine voxels F c .. F c + F - 1: its centre is at fine index F c + (F - 1) / 2.
  const double                     F = static_cast<double>(m_Factor);
  DRRAttenuationVolume::MatrixType matrix = volume.GetIndexToPhysicalMatrix() * F;
  DRRAttenuationVolume::PointType  origin = volume.GetOrigin();
  const double                     shift = 0.5 * (F - 1.0);
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int a = 0; a < 3; ++a)
    {
      origin[r] += volume.GetIndexToPhysicalMatrix()[r][a] * shift;
    }
  }
  m_CoarseVolume->SetIndexToPhysical(matrix, origin);
}

void
DRRControlVariate::BeginSlabs(const DRRAttenuationVolume::SizeType &   wholeSize,
                              const DRRAttenuationVolume::MatrixType & indexToPhysical,
                              const DRRAttenuationVolume::PointType &  origin,
                              unsigned int                             factor)
{
  VerifyFactor(factor);
  m_Factor = factor;
  m_TotalMass = 0.0;
  m_ResidualVolume = DRRAttenuationVolume::New(); // no residual: each slab has its own
  m_CoarseVolume = DRRAttenuationVolume::New();
  for (unsigned int a = 0; a < 3; ++a)
  {
    m_SlabCoarseSize[a] = (wholeSize[a] + factor - 1) / factor;
  }
  // The coarse volume's own buffer, filled slab by slab and then taken by it (EndSlabs()): no second copy.
  m_SlabCoarseMu.reset(new float[m_SlabCoarseSize[0] * m_SlabCoarseSize[1] * m_SlabCoarseSize[2]]());
  // The coarse grid of the whole (BuildCoarseVolume()): a header with no voxel gives the matrix and origin.
  auto header = DRRAttenuationVolume::New();
  header->SetIndexToPhysical(indexToPhysical, origin);
  this->SetCoarseGrid(*header);
}

void
DRRControlVariate::AddSlab(const DRRControlVariate & slab, uint64_t firstPlane)
{
  const DRRAttenuationVolume & coarse = slab.GetCoarseVolume();
  const uint64_t               plane = m_SlabCoarseSize[0] * m_SlabCoarseSize[1];
  const uint64_t               firstCoarsePlane = firstPlane / m_Factor;
  if (slab.GetFactor() != m_Factor || firstPlane % m_Factor != 0 || coarse.GetSize()[0] != m_SlabCoarseSize[0] ||
      coarse.GetSize()[1] != m_SlabCoarseSize[1] || firstCoarsePlane + coarse.GetSize()[2] > m_SlabCoarseSize[2])
  {
    itkExceptionMacro("the slab's control variate (F " << slab.GetFactor() << ", from plane " << firstPlane
                                                       << ") does not fit the whole one's coarse grid (F " << m_Factor
                                                       << ")");
  }
  const float * mu = coarse.GetMuBuffer();
  if (!m_SlabCoarseMu)
  {
    itkExceptionMacro("AddSlab() outside BeginSlabs() .. EndSlabs()");
  }
  std::copy(mu, mu + plane * coarse.GetSize()[2], m_SlabCoarseMu.get() + plane * firstCoarsePlane);
  m_TotalMass += slab.GetTotalMass();
}

void
DRRControlVariate::EndSlabs(MultiThreaderBase * threader)
{
  const DRRAttenuationVolume::MatrixType matrix = m_CoarseVolume->GetIndexToPhysicalMatrix();
  const DRRAttenuationVolume::PointType  origin = m_CoarseVolume->GetOrigin();
  if (!m_SlabCoarseMu)
  {
    itkExceptionMacro("EndSlabs() without BeginSlabs()");
  }
  m_CoarseVolume->BuildFromMu(m_SlabCoarseSize, std::move(m_SlabCoarseMu), threader);
  m_CoarseVolume->SetIndexToPhysical(matrix, origin);
  this->Modified();
}

double
DRRControlVariate::GetResidualMass() const
{
  return m_ResidualVolume->ComputeTotalMass(); // one pass over the residual on the first call
}

void
DRRControlVariate::AddCoarseImage(const DRRPointProjection & projection,
                                  SplatEnum                  splat,
                                  unsigned int               raysPerSide,
                                  uint64_t                   seed,
                                  MultiThreaderBase *        threader,
                                  ProcessObject *            progressFilter,
                                  DRRPointRenderer::Result & result,
                                  unsigned int               replicates) const
{
  if (m_Factor == 0)
  {
    itkExceptionMacro("AddCoarseImage() needs Build() first");
  }
  std::vector<double>         image;
  std::vector<double>         standardError;
  const DRRExactRayIntegrator integrator(*m_CoarseVolume, PointBasedDRREnums::ReconstructionKernel::Box, m_Factor);
  integrator.RenderFootprintAverages(
    projection, splat, raysPerSide, seed, threader, progressFilter, image, standardError, replicates);
  if (image.size() != result.LineIntegral.size())
  {
    itkExceptionMacro("AddCoarseImage(): the render has " << result.LineIntegral.size() << " pixels, the view "
                                                          << image.size());
  }
  for (size_t p = 0; p < image.size(); ++p)
  {
    result.LineIntegral[p] += image[p];
    result.StandardError[p] =
      std::sqrt(result.StandardError[p] * result.StandardError[p] + standardError[p] * standardError[p]);
  }
  result.RoomMass = m_TotalMass * projection.GetRoomMassScale();
}

unsigned int
DRRControlVariate::ChooseFactor(const DRRAttenuationVolume & volume,
                                const DRRPointProjection &   projection,
                                uint64_t                     samples,
                                uint64_t                     poses)
{
  return ChooseFactor(volume.GetSize(), volume.GetVoxelVolume(), projection, samples, poses);
}

unsigned int
DRRControlVariate::ChooseFactor(const DRRAttenuationVolume::SizeType & size,
                                double                                 voxelVolume,
                                const DRRPointProjection &             projection,
                                uint64_t                               samples,
                                uint64_t                               poses)
{
  double centre[3];
  for (unsigned int a = 0; a < 3; ++a)
  {
    centre[a] = 0.5 * (static_cast<double>(size[a]) - 1.0);
  }
  double column, row, depth;
  projection.ProjectToDetectorPlane(centre, column, row, depth);
  const double pixelPitch = std::sqrt(projection.GetPixelArea()); // mm on the detector
  const double footprint = projection.IsPerspective() && depth > 0.0
                             ? pixelPitch * depth / projection.GetSourceToDetectorDistance()
                             : pixelPitch;         // mm at the volume's centre
  const double voxelSize = std::cbrt(voxelVolume); // mm
  unsigned int factor = 2;
  while (factor < 8 && 2.0 * factor * voxelSize <= footprint)
  {
    factor *= 2;
  }
  if (poses <= 1)
  {
    return factor;
  }
  // Kept points: the coarse image at every pose against the extra points a larger F needs for the same error.
  using Model = AutomaticCostModel;
  const double pixels = static_cast<double>(projection.GetNumberOfColumns()) * projection.GetNumberOfRows();
  const double across = std::cbrt(static_cast<double>(size[0]) * static_cast<double>(size[1]) *
                                  static_cast<double>(size[2])); // voxels along a ray, roughly
  const double perPoint = Model::PointNanoseconds + static_cast<double>(poses - 1) * Model::KeptPointNanoseconds;
  const auto   predicted = [&](unsigned int F) {
    const double coarseImage = static_cast<double>(poses) * pixels *
                               (Model::PixelNanoseconds + Model::PixelNanosecondsPerCoarseVoxel * across / F);
    const double points = static_cast<double>(samples) * std::pow(static_cast<double>(F) / factor,
                                                                  Model::ResidualMassExponent * Model::PointsExponent);
    return coarseImage + perPoint * points;
  };
  unsigned int fastest = factor;
  for (unsigned int F = 2 * factor; F <= 16; F *= 2)
  {
    fastest = predicted(F) < predicted(fastest) ? F : fastest;
  }
  return fastest;
}

size_t
DRRControlVariate::GetTableSizeInBytes() const
{
  return static_cast<size_t>(m_CoarseVolume->GetNumberOfVoxels() * sizeof(float) +
                             m_ResidualVolume->GetBytesPerVoxel() * m_ResidualVolume->GetNumberOfVoxels());
}

void
DRRControlVariate::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Factor: " << m_Factor << std::endl;
  os << indent << "TotalMass (mm^2): " << m_TotalMass << std::endl;
  os << indent << "ResidualMass (mm^2): " << this->GetResidualMass() << std::endl;
  os << indent << "TableSize (bytes): " << this->GetTableSizeInBytes() << std::endl;
}
} // namespace itk
