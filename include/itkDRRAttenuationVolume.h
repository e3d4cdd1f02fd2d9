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

#include "itkDRRCompatibility.h"
#include "itkDataObject.h"
#include "itkObjectFactory.h"
#include "itkImageRegion.h"
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
 * Integer-valued input (CT in HU, whatever the pixel type, whose values span less than 65536) is held as 16-bit keys
 * (the input value less an integer offset) and a table of mu per key, the transfer function folded into it: mu of a
 * voxel is one lookup at the point of use (FillMuRow()). A 16-bit input (int16 HU, the common CT) whose owner is given
 * to Build() is read in place: the volume adds no byte per voxel to the input. Other integer input is copied to keys
 * (2 bytes per voxel). The same input is also grouped into levels, one per input value with mu > 0: the paper's
 * hist[l]. Their counts come with the keys; their voxel lists (GetLevelVoxels(), 4 bytes per non-air voxel) are built
 * on the first call, by the level samplers alone, and mu per voxel (GetMuBuffer(), 4 bytes per voxel) likewise for
 * the consumers that want it. Other input (float HU, mu) is held as mu per voxel. A residual volume
 * (BuildResidual(): |mu - mu_c| of a control variate) holds no voxel either: its rows are computed from the volume
 * and its coarse means when read.
 *
 * Every pass over the voxels runs in parallel over a fixed partition of the voxels into blocks
 * (GetNumberOfBlocks(), GetBlockBegin()) that depends on the size alone, never on the threads; per-block results are
 * merged in block order, so the volume, its levels and its sums are the same bits on any number of threads.
 *
 * A data object of ITK's pipeline: the output of DRRImageToAttenuationVolumeFilter (the preprocessing stage) and an
 * input of the DRR filters, which update it through the pipeline; its modified time is that of its last build, so
 * whatever is derived from it (a sampler's tables, a control variate, kept points) is stale when older. Its regions
 * are regions of the input volume's grid: the largest possible one (the input's), the one requested of the stage (a
 * slab of whole z planes, when a filter streams) and the one it models (buffered). A model holds the voxels of its
 * region and no others, so a request for any other region, smaller too, builds it anew.
 *
 * \sa DRRImageToAttenuationVolumeFilter, DRRImageFilterBase::GetAttenuationVolume(), DRRTransferFunction,
 * DRRAttenuationLevels
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRAttenuationVolume : public DataObject
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRAttenuationVolume);

  /** Standard class type aliases. */
  using Self = DRRAttenuationVolume;
  using Superclass = DataObject;
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

  /** A region of the input volume's grid (index space): the model's largest possible, requested and buffered ones. */
  using RegionType = ImageRegion<3>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRAttenuationVolume);

  /** Builds the volume from input values (size[0] x size[1] x size[2], x fastest) through a transfer function, on
   * the threads of threader (null: platform threads of its own). Integer values spanning less than 65536 give keys and
   * levels, anything else mu per voxel. Throws, naming the first offending voxel in
   * memory order, for a non-finite value or a negative or non-finite attenuation. 16-bit integer values are read in
   * place, not copied, when valueOwner (the image's pixel container) is given: the volume keeps a reference to it, and
   * the values must not change without a new Build(). Defined in itkDRRAttenuationVolume.hxx, for every pixel type. */
  template <typename TValue>
  void
  Build(const TValue *              values,
        const SizeType &            size,
        const DRRTransferFunction & transfer,
        MultiThreaderBase *         threader,
        const LightObject *         valueOwner = nullptr);

  /** Builds a volume of mu per voxel (no levels) computed by fill for the voxels of every fixed block, on the threads
   * of threader (null: platform threads of its own): for volumes derived from another one (DRRControlVariate's coarse
   * and residual volumes), without a copy of input values. Throws, naming the first offending voxel in memory order,
   * for a negative or non-finite mu. The index-to-physical mapping is left as it was. */
  void
  BuildFromMu(const SizeType & size, const MuFunctionType & fill, MultiThreaderBase * threader);
#if !defined(ITK_WRAPPING_PARSER)
  /** The same from a buffer of mu (1/mm) per voxel already filled (size's voxels, x fastest), which the volume takes:
   * no copy. Not wrapped: SWIG passes arguments by copy, and a std::unique_ptr cannot be copied. */
  void
  BuildFromMu(const SizeType & size, std::unique_ptr<float[]> mu, MultiThreaderBase * threader);
#endif

  /** Makes this volume the residual of a control variate: |mu_v - mu_c(block of v)| (1/mm) on the grid of fine padded
   * to a multiple of factor per axis (the padding is air in fine), where coarse holds the block means mu_c, one voxel
   * per factor^3 block. No voxel is stored: FillMuRow() computes a row from fine's rows and coarse's row, and
   * FillResidualRow() gives the signed residual. Both volumes are kept (referenced). The extremes and the sum of |r|
   * (in the fixed blocks' order, as a volume of mu per voxel would give them) take one pass, made when first asked
   * for. The index-to-physical mapping is fine's. */
  void
  BuildResidual(const DRRAttenuationVolume & fine, const DRRAttenuationVolume & coarse, unsigned int factor);

  /** mu (1/mm) of the count voxels (i .. i + count - 1, j, k) of one row, all inside the grid, into out: a lookup of
   * the keys, a copy of mu, or the residual computed. Thread-safe; the cheap way to read the volume by rows. */
  void
  FillMuRow(uint64_t i, uint64_t j, uint64_t k, uint64_t count, float * out) const
  {
    const uint64_t first = i + m_Size[0] * (j + m_Size[1] * k);
    if (m_Keys)
    {
      const uint16_t * keys = m_Keys + first;
      const float *    table = m_KeyMu.data();
      const uint16_t   flip = m_KeyFlip;
      for (uint64_t x = 0; x < count; ++x)
      {
        out[x] = table[static_cast<uint16_t>(keys[x] ^ flip)];
      }
      return;
    }
    this->FillMuRowSlow(first, i, j, k, count, out);
  }

  /** mu (1/mm) of the box of voxels [i, i + ni) x [j, j + nj) x [k, k + nk), all inside the grid, into out (x fastest,
   * ni nj nk values): one call for a sampler's group of voxels, whatever the volume holds. */
  void
  FillMuBox(uint64_t i, uint64_t j, uint64_t k, uint64_t ni, uint64_t nj, uint64_t nk, float * out) const;

  /** Asks the memory for the voxels of a box (as FillMuBox() takes it) ahead of reading them: a hint, which changes no
   * result. A sampler's walk reads one small box after another from all over the volume: each a wait for memory,
   * unless asked for while the last box is worked on. */
  void
  PrefetchBox(uint64_t i, uint64_t j, uint64_t k, uint64_t ni, uint64_t nj, uint64_t nk) const;

  /** Reads mu (1/mm) by linear voxel index (x fastest) in the hot loops of the exact projectors: a key lookup for a
   * volume of keys, else mu per voxel. Copyable, valid while the volume is unchanged. */
  class MuReader
  {
  public:
    /** mu (1/mm) of voxel v (linear index, x fastest). */
    float
    operator()(uint64_t v) const
    {
      return m_Keys ? m_Table[static_cast<uint16_t>(m_Keys[v] ^ m_Flip)] : m_Mu[v];
    }
    /** Bytes read per voxel: a key's, or a float's. */
    unsigned int
    GetBytesPerVoxel() const
    {
      return m_Keys ? sizeof(uint16_t) : sizeof(float);
    }

  private:
    friend class DRRAttenuationVolume;
    const uint16_t * m_Keys{ nullptr };
    uint16_t         m_Flip{ 0 };
    const float *    m_Table{ nullptr };
    const float *    m_Mu{ nullptr };
  };
  /** A MuReader of this volume (materializes mu per voxel for a volume without keys: a residual, a masked volume). */
  MuReader
  GetMuReader() const
  {
    MuReader reader;
    if (m_Keys)
    {
      reader.m_Keys = m_Keys;
      reader.m_Flip = m_KeyFlip;
      reader.m_Table = m_KeyMu.data();
    }
    else
    {
      reader.m_Mu = this->GetMuBuffer();
    }
    return reader;
  }

  /** The signed residual r = mu - mu_c (1/mm) of count voxels of a row of a residual volume (BuildResidual()); throws
   * for another volume. */
  void
  FillResidualRow(uint64_t i, uint64_t j, uint64_t k, uint64_t count, double * out) const;

  /** True if the signed residual r = mu - mu_c of voxel (i, j, k) of a residual volume (BuildResidual()) is negative:
   * a point drawn there carries a negative weight. The test of FillResidualRow()'s double arithmetic, for one voxel:
   * the renderer asks it per point instead of holding a sign per voxel. */
  bool
  IsNegativeResidual(uint64_t i, uint64_t j, uint64_t k) const
  {
    const SizeType & fine = m_ResidualFine->GetSize();
    const double     value = i < fine[0] && j < fine[1] && k < fine[2]
                               ? static_cast<double>(m_ResidualFineReader(i + fine[0] * (j + fine[1] * k)))
                               : 0.0;
    const SizeType & coarse = m_ResidualCoarse->GetSize();
    return value - static_cast<double>(
                     m_ResidualCoarseMu[this->CoarseIndex(i) +
                                        coarse[0] * (this->CoarseIndex(j) + coarse[1] * this->CoarseIndex(k))]) <
           0.0;
  }

  /** True for a residual volume (BuildResidual()). */
  bool
  IsResidual() const
  {
    return m_ResidualCoarse.IsNotNull();
  }

  /** Bytes this volume holds per voxel of its grid beyond its input (keys copied, mu, level lists, channels), for
   * `pbdrr -v`: 0 for a 16-bit CT read in place with nothing else asked for. */
  double
  GetBytesPerVoxel() const;

  /** Makes every voxel v with keep[v] == 0 air (x fastest, one entry per voxel): mu 0, in no level, never sampled.
   * The labels a render leaves out (DRRImageFilterBase::SetKeptLabels()). Levels keep their order and mu; levels left
   * empty are removed. A volume of keys stays one, the masked voxels set to an air key of its range (a copy of the
   * keys, 2 bytes per voxel); one whose every key in range attenuates keeps its level lists, compacted, and mu per
   * voxel. */
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
  /** What the channel outputs of a render of this volume are: the label (label channels) or the material index
   * (material channels) of each, in channel order; empty, the default, for no channel outputs. One entry with no voxel
   * channels is a channel output equal to the projection. */
  void
  SetChannelLabels(std::vector<uint16_t> labels)
  {
    m_ChannelLabels = std::move(labels);
    this->Modified();
  }
  /** The labels of the channel outputs (empty: none). */
  const std::vector<uint16_t> &
  GetChannelLabels() const
  {
    return m_ChannelLabels;
  }

  /** Releases everything: an empty volume (size 0), as before a build, and no buffered region. ITK's pipeline calls it
   * to release data. */
  void
  Initialize() override;

  ///@{
  /** The region of the input's grid a model can cover: the input volume's largest possible region (set by the stage's
   * GenerateOutputInformation()); empty for a model built by hand. */
  void
  SetLargestPossibleRegion(const RegionType & region);
  const RegionType &
  GetLargestPossibleRegion() const
  {
    return m_LargestPossibleRegion;
  }
  ///@}
  ///@{
  /** The region asked of the stage: whole z planes of the largest possible region (a slab, when streaming). Empty
   * until the pipeline sets it: then the largest possible region. */
  void
  SetRequestedRegion(const RegionType & region);
  const RegionType &
  GetRequestedRegion() const
  {
    return m_RequestedRegion;
  }
  ///@}
  ///@{
  /** The region the model holds (set by its stage with each build; empty for a model built by hand). */
  void
  SetBufferedRegion(const RegionType & region);
  const RegionType &
  GetBufferedRegion() const
  {
    return m_BufferedRegion;
  }
  ///@}

  /** ITK's pipeline: the source's information, then the requested region, if none was set, the largest possible. */
  void
  UpdateOutputInformation() override;
  /** ITK's pipeline: the whole input volume requested. */
  void
  SetRequestedRegionToLargestPossibleRegion() override;
  /** ITK's pipeline: true if the model holds other voxels than those requested (more as well: a slab's model must not
   * render its neighbours' voxels). */
  bool
  RequestedRegionIsOutsideOfTheBufferedRegion() override;
  /** ITK's pipeline: the requested region lies within the largest possible one. */
  bool
  VerifyRequestedRegion() override;
  /** ITK's pipeline: the requested region of another model. */
  void
  SetRequestedRegion(const DataObject * data) override;
  /** ITK's pipeline: the largest possible region of another model. */
  void
  CopyInformation(const DataObject * data) override;

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
  /** The non-air voxels (linear index, x fastest) grouped by level, increasing within a level. Built on the first call
   * (in parallel, thread-safe; 4 bytes per non-air voxel; volumes of fewer than 2^32 voxels); valid until the next
   * Build(). */
  const uint32_t *
  GetLevelVoxels() const
  {
    return m_LevelVoxelsReady.load(std::memory_order_acquire) ? m_LevelVoxels.get() : this->MaterializeLevelVoxels();
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
  /** ParallelizeBlocks() for tasks that need room of their own (rows read ahead, sums): makeWorker() is called once
   * per worker, on the worker's thread, and returns the function that worker runs on each block it takes. */
  static void
  ParallelizeBlocksPerWorker(uint64_t                                   numberOfBlocks,
                             const std::function<BlockFunctionType()> & makeWorker,
                             MultiThreaderBase *                        threader);

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
    this->EnsureResidualStatistics();
    return m_LargestMu;
  }
  /** Smallest positive mu, 1/mm (kept from Build(); 0 for an all-air volume). */
  double
  GetSmallestPositiveMu() const
  {
    this->EnsureResidualStatistics();
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
  /** CountIntegerKeys() of integer values (at most 32 bits) from an integer offset: each block's keys bounded by its
   * extremes. */
  template <typename TValue>
  bool
  CountIntegerKeysInRange(const TValue *      values,
                          int64_t             offset,
                          KeyCounts &         counts,
                          MultiThreaderBase * threader) const;
  template <typename TValue>
  void
  BuildLevels(const TValue * values, double offset, KeyCounts && counts, const DRRTransferFunction & transfer);
  template <typename TValue>
  void
  BuildMu(const TValue * values, const DRRTransferFunction & transfer, MultiThreaderBase * threader);

  /** Starts a Build(): sets the size, drops mu and the levels. */
  void
  Reset(const SizeType & size);
  /** Checks the mu buffer (filled first by fill, if not null) and finishes its statistics, block by block. */
  void
  FinishMuBuffer(const MuFunctionType * fill, MultiThreaderBase * threader);
  /** Throws for a failed voxel (Failure::Voxel < number of voxels). */
  void
  ThrowFailure(const Failure & failure) const;
  /** Ends a build of mu per voxel from the per-block checks and extremes of its fill: throws for the first failed
   * voxel (emptying the volume), else keeps the extremes and marks mu ready. */
  void
  FinishMu(const std::vector<Failure> & failures,
           const std::vector<float> &   smallest,
           const std::vector<float> &   largest);
  /** Fills mu from the keys, the levels or the residual's rows, once. */
  const float *
  MaterializeMu() const;
  /** A residual volume's sum and extremes, computed by one pass on the first request (the stratified sampler and the
   * control variate never ask). */
  void
  EnsureResidualStatistics() const
  {
    if (m_ResidualCoarse.IsNotNull() && !m_ResidualStatisticsReady.load(std::memory_order_acquire))
    {
      this->ComputeResidualStatistics();
    }
  }
  void
  ComputeResidualStatistics() const;
  /** Forgets the keys (a mask made some voxels air). */
  void
  DropKeys();
  /** Sorts the voxels by level from the keys, once. */
  const uint32_t *
  MaterializeLevelVoxels() const;
  /** The coarse index (fine index / factor) of a residual volume: a shift for the usual factors, which the sampler's
   * walk and the renderer's signs ask for per row and per point, where a division would cost more than the rest. */
  uint64_t
  CoarseIndex(uint64_t fine) const
  {
    return m_ResidualShift < 64 ? fine >> m_ResidualShift : fine / m_ResidualFactor;
  }

  /** ApplyVoxelMask() on the keys: a copy of them with the masked voxels set to an air key of the volume's range, and
   * the levels recounted. False (nothing changed) without keys, or without an air key in the range. */
  bool
  MaskKeys(const uint8_t * keep, MultiThreaderBase * threader);

  /** FillMuRow() of a volume without keys: from mu per voxel (materialized if needed) or the residual. */
  void
  FillMuRowSlow(uint64_t first, uint64_t i, uint64_t j, uint64_t k, uint64_t count, float * out) const;
  /** Calls function(v, mu, n) for the voxels [begin, end) in runs of at most one row, mu holding their n values. */
  template <typename TFunction>
  void
  ForEachMuRun(uint64_t begin, uint64_t end, TFunction && function) const;
  /** Holds the keys of 16-bit input in place (read through keyFlip), or a copy of value - offset. */
  template <typename TValue>
  void
  KeepKeys(const TValue * values, double offset, MultiThreaderBase * threader, const LightObject * valueOwner);

  SizeType                            m_Size{ { 0, 0, 0 } };
  mutable std::unique_ptr<float[]>    m_Mu;
  mutable std::atomic<bool>           m_MuReady{ false };
  mutable std::mutex                  m_MuMutex;
  std::vector<float>                  m_LevelMu;
  std::vector<uint64_t>               m_LevelStart;
  mutable std::unique_ptr<uint32_t[]> m_LevelVoxels;
  mutable std::atomic<bool>           m_LevelVoxelsReady{ false };
  mutable std::mutex                  m_LevelVoxelsMutex;
  KeyCounts                           m_KeyCounts;  // per-block key counts, for the level lists
  std::vector<uint32_t>               m_LevelOfKey; // level of key - lowest key, or none (air)
  uint32_t                            m_LowestKey{ 0 };
  // Keys: value - offset of every voxel, read as stored ^ m_KeyFlip (the input in place, or m_OwnKeys).
  const uint16_t *            m_Keys{ nullptr };
  uint16_t                    m_KeyFlip{ 0 };
  std::unique_ptr<uint16_t[]> m_OwnKeys;
  LightObject::ConstPointer   m_KeyOwner;
  std::vector<float>          m_KeyMu; // mu (1/mm) of every key, 0 for air and absent keys
  // Residual of a control variate (BuildResidual()).
  ConstPointer              m_ResidualFine;
  ConstPointer              m_ResidualCoarse;
  uint64_t                  m_ResidualFactor{ 0 };
  unsigned int              m_ResidualShift{ 64 }; // log2 of the factor if a power of two, else 64
  MuReader                  m_ResidualFineReader;
  const float *             m_ResidualCoarseMu{ nullptr };
  mutable double            m_ResidualMuSum{ 0.0 };
  mutable std::atomic<bool> m_ResidualStatisticsReady{ false };
  mutable float             m_SmallestPositiveMu{ 0.0f };
  mutable float             m_LargestMu{ 0.0f };
  MatrixType                m_IndexToPhysical;
  PointType                 m_Origin;
  std::vector<uint8_t>      m_VoxelChannels;
  unsigned int              m_NumberOfChannels{ 1 };
  std::vector<uint16_t>     m_ChannelLabels;
  RegionType                m_LargestPossibleRegion;
  RegionType                m_RequestedRegion;
  RegionType                m_BufferedRegion;
};
} // namespace itk

#include "itkDRRAttenuationVolume.hxx"

#endif
