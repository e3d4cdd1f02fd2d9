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
#ifndef itkDRRPointCloud_h
#define itkDRRPointCloud_h

#include "itkDRRCompatibility.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include "itkPointBasedDRREnums.h"
#include "PointBasedDRRExport.h"

#include <array>
#include <vector>

namespace itk
{
/** \class DRRPointCloud
 * \brief The points of one point-based render, kept so that other poses re-project them without sampling again.
 *
 * A point is its position as a continuous voxel index of the volume it was drawn from (single precision: 12 bytes,
 * a rounding below 2^-13 voxel for volumes under 1024 voxels a side, far below any pixel), plus only what the
 * estimator needs: its sampler weight (stored only if some weight differs from 1) and its stratum (stored only
 * for dependent samplers, which render as R independent strata). Points are kept in the order the sampler drew
 * them: the stratified sampler's walk is spatially coherent, which keeps the splat's pixel writes cache-local.
 *
 * The cloud covers the whole volume (no culling), so it serves every view. Re-projecting it with a transform and
 * geometry gives exactly (bit for bit) what a fresh render of the same seed drawing the same cloud gives: frozen
 * noise, which makes a similarity metric a smooth function of the pose.
 *
 * Built by DRRPointRenderer::Draw(); rendered by DRRPointRenderer::Render(cloud, ...).
 *
 * \sa PointBasedDRRImageFilter::SetReusePoints()
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPointCloud : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRPointCloud);

  /** Standard class type aliases. */
  using Self = DRRPointCloud;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  /** Box or Tent reconstruction kernel. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRPointCloud);

  /** How the points were drawn: what a render of them needs besides the points. */
  struct Description
  {
    uint64_t              NumberOfRequestedSamples{ 0 }; ///< N asked for (the cloud may hold R ceil(N / R))
    uint64_t              NumberOfStrata{ 1 };           ///< independent strata (1: independent points)
    bool                  InterleavedStrata{ false };    ///< strata share one run (stratified sampler)
    double                SampledMass{ 0.0 };            ///< mm^2, volume frame: what the points stand for
    double                MaximumWeight{ 1.0 };          ///< largest sampler weight
    KernelEnum            Kernel{ KernelEnum::Box };     ///< reconstruction kernel that placed the points
    std::array<double, 3> SupportLower{};                ///< continuous-index box the points lie in: lower corner
    std::array<double, 3> SupportUpper{};                ///< continuous-index box the points lie in: upper corner
    std::array<size_t, 3> VolumeSize{};                  ///< voxels of the volume drawn from (x, y, z)
    uint64_t              Seed{ 0 };                     ///< seed the points were drawn with
    unsigned int          NumberOfChannels{ 1 };         ///< channels of the voxels (1: no channels kept)
  };

  /** Sizes the cloud for numberOfPoints points (weights and strata only if asked for; a channel per point if the
   * description has more than one) and sets its description. */
  void
  Allocate(uint64_t numberOfPoints, bool withWeights, bool withStrata, const Description & description);

  /** How the points were drawn. */
  const Description &
  GetDescription() const
  {
    return m_Description;
  }

  /** Number of points held. */
  uint64_t
  GetNumberOfPoints() const
  {
    return m_X.size();
  }

  ///@{
  /** Positions (continuous voxel index), one array per axis. */
  float *
  GetX()
  {
    return m_X.data();
  }
  float *
  GetY()
  {
    return m_Y.data();
  }
  float *
  GetZ()
  {
    return m_Z.data();
  }
  const float *
  GetX() const
  {
    return m_X.data();
  }
  const float *
  GetY() const
  {
    return m_Y.data();
  }
  const float *
  GetZ() const
  {
    return m_Z.data();
  }
  ///@}
  ///@{
  /** Sampler weights, or null if every weight is 1. */
  float *
  GetWeights()
  {
    return m_Weight.empty() ? nullptr : m_Weight.data();
  }
  const float *
  GetWeights() const
  {
    return m_Weight.empty() ? nullptr : m_Weight.data();
  }
  ///@}
  ///@{
  /** Stratum of every point, or null with one stratum. */
  uint8_t *
  GetStrata()
  {
    return m_Stratum.empty() ? nullptr : m_Stratum.data();
  }
  const uint8_t *
  GetStrata() const
  {
    return m_Stratum.empty() ? nullptr : m_Stratum.data();
  }
  ///@}
  ///@{
  /** Channel of every point (the channel of the voxel it was drawn in, DRRAttenuationVolume::GetVoxelChannels()), or
   * null with one channel. */
  uint8_t *
  GetChannels()
  {
    return m_Channel.empty() ? nullptr : m_Channel.data();
  }
  const uint8_t *
  GetChannels() const
  {
    return m_Channel.empty() ? nullptr : m_Channel.data();
  }
  ///@}

  /** Memory held by the points, bytes. */
  size_t
  GetSizeInBytes() const;
  /** Memory held per point, bytes: 12 for the positions, plus 4 with weights, 1 with strata and 1 with channels
   * (0 for an empty cloud). */
  double
  GetBytesPerPoint() const;

protected:
  DRRPointCloud() = default;
  ~DRRPointCloud() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  std::vector<float>   m_X;
  std::vector<float>   m_Y;
  std::vector<float>   m_Z;
  std::vector<float>   m_Weight;
  std::vector<uint8_t> m_Stratum;
  std::vector<uint8_t> m_Channel;
  Description          m_Description;
};
} // namespace itk

#endif
