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
#ifndef itkDRRAttenuationVolume_h
#define itkDRRAttenuationVolume_h

#include "itkObject.h"
#include "itkObjectFactory.h"
#include "itkMatrix.h"
#include "itkPoint.h"
#include "itkMultiThreaderBase.h"
#include "PointBasedDRRExport.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace itk
{
class DRRTransferFunction;

/** \class DRRAttenuationVolume
 * \brief The attenuation model the DRR filters render: mu (1/mm) on the voxel grid, with the grid's
 * index-to-physical mapping.
 *
 * Voxel (i, j, k) covers [i - 0.5, i + 0.5] x [j - 0.5, j + 0.5] x [k - 0.5, k + 0.5] in continuous index space;
 * physical = Origin + IndexToPhysical * index (IndexToPhysical = direction * diag(spacing), mm per index). The
 * filters build it once per input and transfer function (Build()); the samplers and exact projectors only read it.
 *
 * Integer-valued input (CT in HU, whatever the pixel type, whose values span less than 65536) is held as levels: the
 * non-air voxels grouped by input value, one level per value, each with its one mu. That is the paper's hist[l],
 * which the level samplers draw from as it is, and a lossless form of mu: mu per voxel is then materialized from the
 * levels only when something asks for it (GetMuBuffer()), which the level samplers never do. Levels take 4 bytes per
 * non-air voxel, mu 4 bytes per voxel. Other input is held as mu per voxel.
 *
 * Every pass over the voxels runs in parallel over a fixed partition of the voxels into blocks
 * (GetNumberOfBlocks(), GetBlockBegin()) that depends on the size alone, never on the threads; per-block results are
 * merged in block order, so the volume, its levels and its sums are the same bits on any number of threads.
 *
 * \sa DRRImageFilterBase::GetAttenuationVolume(), DRRTransferFunction, DRRAttenuationLevels
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRAttenuationVolume : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRAttenuationVolume);

  /** Standard class type aliases. */
  using Self = DRRAttenuationVolume;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  /** Grid size in voxels (x, y, z). */
  using SizeType = std::array<uint64_t, 3>;
  /** The index-to-physical matrix, mm per index. */
  using MatrixType = Matrix<double, 3, 3>;
  /** A physical point, mm. */
  using PointType = Point<double, 3>;
  /** A task run for each block of voxels by ParallelizeBlocks(). */
  using BlockFunctionType = std::function<void(uint64_t block)>;
  /** Fills mu (1/mm) of the voxels [begin, end) (linear index, x fastest) for BuildFromMu(). */
  using MuFunctionType = std::function<void(uint64_t begin, uint64_t end, float * mu)>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkTypeMacro(DRRAttenuationVolume, Object);

  /** Builds the volume from input values (size[0] x size[1] x size[2], x fastest) through a transfer function, on
   * the threads of threader (null: platform threads of its own). Integer values spanning less than 65536 (in volumes of
   * fewer than 2^32 - 128 voxels) give levels, anything else mu per voxel. Throws, naming the first offending voxel in
   * memory order, for a non-finite value or a negative or non-finite attenuation. Defined in
   * itkDRRAttenuationVolume.hxx, for every pixel type. */
  template <typename TValue>
  void
  Build(const TValue *              values,
        const SizeType &            size,
        const DRRTransferFunction & transfer,
        MultiThreaderBase *         threader);

  /** Builds a volume of mu per voxel (no levels) computed by fill for the voxels of every fixed block, on the threads
   * of threader (null: platform threads of its own): for volumes derived from another one (DRRControlVariate's coarse
   * and residual volumes), without a copy of input values. Throws, naming the first offending voxel in memory order,
   * for a negative or non-finite mu. The index-to-physical mapping is left as it was. */
  void
  BuildFromMu(const SizeType & size, const MuFunctionType & fill, MultiThreaderBase * threader);

  /** Makes every voxel v with keep[v] == 0 air (x fastest, one entry per voxel): mu 0, in no level, never sampled.
   * The labels a render leaves out (DRRImageFilterBase::SetKeptLabels()). Levels keep their order and mu; levels left
   * empty are removed. */
  void
  ApplyVoxelMask(const uint8_t * keep, MultiThreaderBase * threader);

  /** Gives every voxel a channel, 0 to numberOfChannels - 1 (x fastest, one entry per voxel; 2 to 256 channels), or
   * none (an empty vector and 1): a point drawn in a voxel adds to the voxel's channel image
   * (DRRPointRenderer::Settings::VoxelChannels), and the exact projectors integrate each channel's voxels apart. */
  void
  SetVoxelChannels(std::vector<uint8_t> channels, unsigned int numberOfChannels);
  /** The channel of every voxel, or null without channels. */
  const uint8_t *
  GetVoxelChannels() const
  {
    return m_VoxelChannels.empty() ? nullptr : m_VoxelChannels.data();
  }
  /** Number of channels (1 without channels). */
  unsigned int
  GetNumberOfChannels() const
  {
    return m_NumberOfChannels;
  }

  /** Grid size in voxels (x, y, z). */
  const SizeType &
  GetSize() const
  {
    return m_Size;
  }
  /** Number of voxels, size[0] x size[1] x size[2]. */
  uint64_t
  GetNumberOfVoxels() const
  {
    return m_Size[0] * m_Size[1] * m_Size[2];
  }

  /** mu (1/mm), x fastest. A volume of levels materializes it on the first call (in parallel, thread-safe; it costs
   * about as much as building the levels and 4 bytes per voxel); the pointer stays valid until the next Build(). */
  const float *
  GetMuBuffer() const
  {
    return m_MuReady.load(std::memory_order_acquire) ? m_Mu.get() : this->MaterializeMu();
  }
  /** mu at an integer index, zero outside the grid (the zero padding of the tent model). */
  float
  GetMuOrZero(int64_t i, int64_t j, int64_t k) const
  {
    if (i < 0 || j < 0 || k < 0 || static_cast<uint64_t>(i) >= m_Size[0] || static_cast<uint64_t>(j) >= m_Size[1] ||
        static_cast<uint64_t>(k) >= m_Size[2])
    {
      return 0.0f;
    }
    return this->GetMuBuffer()[static_cast<uint64_t>(i) +
                               m_Size[0] * (static_cast<uint64_t>(j) + m_Size[1] * static_cast<uint64_t>(k))];
  }

  /** True if the volume is held as levels (integer-valued input). */
  bool
  HasLevels() const
  {
    return !m_LevelStart.empty();
  }
  /** Number of levels: distinct input values with mu > 0. */
  size_t
  GetNumberOfLevels() const
  {
    return m_LevelMu.size();
  }
  /** mu of every voxel of a level, 1/mm (> 0). Levels are in increasing input value. */
  float
  GetLevelMu(size_t level) const
  {
    return m_LevelMu[level];
  }
  /** First entry of a level in GetLevelVoxels(); GetLevelStart(GetNumberOfLevels()) is the number of non-air voxels. */
  uint64_t
  GetLevelStart(size_t level) const
  {
    return m_LevelStart[level];
  }
  /** The non-air voxels (linear index, x fastest) grouped by level, increasing within a level. */
  const uint32_t *
  GetLevelVoxels() const
  {
    return m_LevelVoxels.get();
  }

  /** The fixed partition of the voxels used by every parallel pass: block b holds the voxels
   * [GetBlockBegin(b), GetBlockBegin(b + 1)). */
  uint64_t
  GetNumberOfBlocks() const
  {
    return ComputeNumberOfBlocks(this->GetNumberOfVoxels());
  }
  /** First voxel (linear index) of a block; GetBlockBegin(GetNumberOfBlocks()) is the number of voxels. */
  uint64_t
  GetBlockBegin(uint64_t block) const
  {
    return this->GetNumberOfVoxels() * block / this->GetNumberOfBlocks();
  }
  /** Number of blocks of the partition of a volume of numberOfVoxels voxels: at most 128, of at least 2^16 voxels. */
  static uint64_t
  ComputeNumberOfBlocks(uint64_t numberOfVoxels);

  /** Calls function(block) once for every block in [0, numberOfBlocks), blocks handed out dynamically to the threads
   * of threader (null: platform threads of its own, never a pool the caller may be running on). Results that depend on
   * the block alone are thread-independent. */
  static void
  ParallelizeBlocks(uint64_t numberOfBlocks, const BlockFunctionType & function, MultiThreaderBase * threader);

  /** Index-to-physical mapping: physical = origin + matrix * continuous index (mm). */
  void
  SetIndexToPhysical(const MatrixType & indexToPhysical, const PointType & origin);
  /** Index-to-physical matrix (direction * diag(spacing)), mm per index. */
  const MatrixType &
  GetIndexToPhysicalMatrix() const
  {
    return m_IndexToPhysical;
  }
  /** Physical position of the centre of voxel (0, 0, 0), mm. */
  const PointType &
  GetOrigin() const
  {
    return m_Origin;
  }

  /** Volume of one voxel, mm^3 (|det IndexToPhysical|). */
  double
  GetVoxelVolume() const;

  /** Sum of mu over the voxels, 1/mm, in a fixed order (levels in order, or fixed blocks in order). */
  double
  ComputeMuSum() const;

  /** Total attenuation mass M = sum of mu * voxel volume, mm^2, accumulated in a fixed order. */
  double
  ComputeTotalMass() const;

  /** Largest mu, 1/mm (kept from Build()). */
  double
  ComputeMaximumMu() const
  {
    return m_LargestMu;
  }
  /** Smallest positive mu, 1/mm (kept from Build(); 0 for an all-air volume). */
  double
  GetSmallestPositiveMu() const
  {
    return m_SmallestPositiveMu;
  }

protected:
  DRRAttenuationVolume();
  ~DRRAttenuationVolume() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** A voxel that failed a check, and why; Voxel is the number of voxels when none did. */
  struct Failure
  {
    uint64_t Voxel{ 0 };
    double   Value{ 0.0 };
    double   Attenuation{ 0.0 };
    bool     NonFinite{ false };
  };

  /** Per-block counts of the integer keys value - offset, each block's over [Lowest[b], Lowest[b] + size). */
  struct KeyCounts
  {
    std::vector<uint32_t>              Lowest;
    std::vector<std::vector<uint32_t>> Counts;
  };

  template <typename TValue>
  bool
  CountIntegerKeys(const TValue * values, double offset, KeyCounts & counts, MultiThreaderBase * threader) const;
  template <typename TValue>
  void
  BuildLevels(const TValue *              values,
              double                      offset,
              const KeyCounts &           counts,
              const DRRTransferFunction & transfer,
              MultiThreaderBase *         threader);
  template <typename TValue>
  void
  BuildMu(const TValue * values, const DRRTransferFunction & transfer, MultiThreaderBase * threader);

  /** Starts a Build(): sets the size, drops mu and the levels. */
  void
  Reset(const SizeType & size);
  /** Throws for a failed voxel (Failure::Voxel < number of voxels). */
  void
  ThrowFailure(const Failure & failure) const;
  /** Ends a build of mu per voxel from the per-block checks and extremes of its fill: throws for the first failed
   * voxel (emptying the volume), else keeps the extremes and marks mu ready. */
  void
  FinishMu(const std::vector<Failure> & failures,
           const std::vector<float> &   smallest,
           const std::vector<float> &   largest);
  /** Fills mu from the levels, once. */
  const float *
  MaterializeMu() const;

  SizeType                         m_Size{ { 0, 0, 0 } };
  mutable std::unique_ptr<float[]> m_Mu;
  mutable std::atomic<bool>        m_MuReady{ false };
  mutable std::mutex               m_MuMutex;
  std::vector<float>               m_LevelMu;
  std::vector<uint64_t>            m_LevelStart;
  std::unique_ptr<uint32_t[]>      m_LevelVoxels;
  float                            m_SmallestPositiveMu{ 0.0f };
  float                            m_LargestMu{ 0.0f };
  MatrixType                       m_IndexToPhysical;
  PointType                        m_Origin;
  std::vector<uint8_t>             m_VoxelChannels;
  unsigned int                     m_NumberOfChannels{ 1 };
};
} // namespace itk

#include "itkDRRAttenuationVolume.hxx"

#endif
