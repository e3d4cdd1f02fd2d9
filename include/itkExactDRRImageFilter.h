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
#ifndef itkExactDRRImageFilter_h
#define itkExactDRRImageFilter_h

#include "itkDRRCompatibility.h"
#include "itkDRRImageFilterBase.h"

namespace itk
{
/** \class ExactDRRImageFilter
 * \brief Deterministic DRR: exact line integrals through the box (Siddon) or tent (trilinear) voxel model, averaged
 * over k x k rays per pixel.
 *
 * The same geometry, transform, transfer function and output modes as PointBasedDRRImageFilter, so it is both the
 * reference the point-based estimate converges to (with the same reconstruction kernel) and a DRR for users who
 * need one without noise. Unlike plastimatch it keeps the exit voxel; unlike itk::RayCastInterpolateImageFunction it
 * keeps the outer half-voxel shell of the volume and honours the direction matrix.
 *
 * \sa PointBasedDRRImageFilter, DRRExactRayIntegrator
 * \ingroup PointBasedDRR
 */
template <typename TInputImage, typename TOutputImage>
class ITK_TEMPLATE_EXPORT ExactDRRImageFilter : public DRRImageFilterBase<TInputImage, TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(ExactDRRImageFilter);

  /** Standard class type aliases. */
  using Self = ExactDRRImageFilter;
  using Superclass = DRRImageFilterBase<TInputImage, TOutputImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  /** Box (Siddon) or Tent (trilinear) voxel model. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(ExactDRRImageFilter);

  ///@{
  /** Box (default): Siddon through the piecewise-constant model. Tent: exact trilinear integral. */
  itkSetEnumMacro(ReconstructionKernel, KernelEnum);
  itkGetConstMacro(ReconstructionKernel, KernelEnum);
  ///@}

  ///@{
  /** Streaming (issue 30): the volume is read and integrated in this many slabs of whole z planes (its slowest axis),
   * each requested from the pipeline in turn (ITK's requested regions: a streaming reader, as MetaImage's, NRRD's or
   * uncompressed NIfTI's, reads only that slab), so that the render holds one slab and its attenuation model at a
   * time. Every ray's integral is the sum of its parts in the slabs it crosses (Siddon's segments end on the same
   * planes), so the projection equals the unstreamed one to rounding. 1 (the default) reads the whole volume at once;
   * more slabs than z planes are as many slabs as planes. Box kernel only (a tent voxel reaches into the next slab);
   * not with labels, material channels or a shared attenuation volume. */
  itkSetClampMacro(NumberOfStreamDivisions, unsigned int, 1, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfStreamDivisions, unsigned int);
  ///@}

  ///@{
  /** k: rays per pixel side (k x k rays per pixel, at the centres of a regular subdivision), 1 to 1024. Default 1. */
  itkSetClampMacro(RaysPerPixelSide, unsigned int, 1, 1024);
  itkGetConstMacro(RaysPerPixelSide, unsigned int);
  ///@}

protected:
  ExactDRRImageFilter() = default;
  ~ExactDRRImageFilter() override = default;

  /** Integrates k x k rays per pixel through the volume (slab by slab when streaming) and writes the output. */
  void
  GenerateData() override;
  /** The whole volume, or when streaming its first slab (the others are requested by GenerateData()). */
  void
  GenerateInputRequestedRegion() override;
  /** The base's rules, and streaming's: the box kernel, no labels or channels, the volume as input. */
  void
  VerifyPreconditions() const override;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** Number of slabs the volume is streamed in: NumberOfStreamDivisions, at most one per z plane. */
  unsigned int
  GetNumberOfSlabs() const;
  /** Slab number `slab` of the input's largest region: whole z planes, the planes shared out evenly. */
  typename TInputImage::RegionType
  GetSlabRegion(unsigned int slab) const;
  /** The projection as the sum of the slabs' projections, each slab requested from the pipeline and modelled alone. */
  std::vector<double>
  RenderStreamed();

  KernelEnum   m_ReconstructionKernel{ KernelEnum::Box };
  unsigned int m_RaysPerPixelSide{ 1 };
  unsigned int m_NumberOfStreamDivisions{ 1 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkExactDRRImageFilter.hxx"
#endif

#endif
