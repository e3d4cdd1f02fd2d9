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
#ifndef itkDRRImageFilterBase_h
#define itkDRRImageFilterBase_h

#include "itkDRRCompatibility.h"
#include "itkImageToImageFilter.h"
#include "itkTransform.h"
#include "itkDRRAttenuationVolume.h"
#include "itkDRRImageToAttenuationVolumeFilter.h"
#include "itkDRRImageFileIntegrity.h"
#include "itkDRRMemoryBudget.h"
#include "itkDRRLabelSelection.h"
#include "itkVectorImage.h"
#include "itkDRRPointProjection.h"
#include "itkDRRProjectionGeometry.h"
#include "itkDRRTransferFunction.h"

#include <vector>

namespace itk
{
/** \class DRRImageFilterBase
 * \brief What every DRR filter of the module shares: a 3D volume in, a projection out, placed by a
 * DRRProjectionGeometry, with an optional linear transform and a transfer function.
 *
 * - Input: a 3D scalar image (HU, or mu in 1/mm with an Identity transfer function). Its origin, spacing and
 *   direction are honoured; NaN or infinite voxels and negative attenuation are rejected with an exception.
 * - Output: a 2D image (cols x rows, spacing du x dv, origin at the centre of pixel (0, 0) in detector-plane
 *   coordinates, see DRRProjectionGeometry) or a 3D one-slice image placed in the room (direction (u, v, -n)), as
 *   ITK's classic 2D-3D registration uses.
 * - Transform: as in ITK registration and itk::RayCastInterpolateImageFunction, it maps a room point to the
 *   volume's physical frame (moving the volume by its inverse). It must be linear; a scaling part is honoured
 *   (lengths are measured in the room).
 * - OutputMode: LineIntegral (default), Transmission exp(-L), Gray8 / Gray16 (window level / width in line-integral
 *   units; width 0: the automatic window, the image's 0.5th to 99.5th percentile).
 * - Labels (optional, docs/design.md section 13): a label image beside the volume (SetLabelImage()) selects which
 *   voxels attenuate (SetKeptLabels(), SetDroppedLabels()) and, with LabelChannels on, splits the projection into one
 *   line-integral image per label in one render: GetChannelOutput(), a VectorImage with a component per label
 *   (GetChannelLabels()), and GetChannelCovarianceOutput(), the covariance of the components' estimates.
 *
 * The attenuation model (DRRAttenuationVolume) is the output of a preprocessing stage,
 * DRRImageToAttenuationVolumeFilter: the filter's own, fed with its input, label image, transfer function and label
 * settings, or one shared between filters (SetAttenuationVolume()). ITK's pipeline rebuilds it only when one of those
 * changed, not for updates that change only the geometry or the transform, as registration does.
 *
 * \sa PointBasedDRRImageFilter, ExactDRRImageFilter, DRRProjectionGeometry, DRRTransferFunction
 * \ingroup PointBasedDRR
 */
template <typename TInputImage, typename TOutputImage>
class ITK_TEMPLATE_EXPORT DRRImageFilterBase : public ImageToImageFilter<TInputImage, TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRImageFilterBase);

  /** Standard class type aliases. */
  using Self = DRRImageFilterBase;
  using Superclass = ImageToImageFilter<TInputImage, TOutputImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRImageFilterBase);

  /** The 3D volume: HU, or mu in 1/mm (any scalar pixel type). */
  using InputImageType = TInputImage;
  /** Voxel type of the volume. */
  using InputPixelType = typename InputImageType::PixelType;
  /** The projection: 2D, or 3D with one slice. */
  using OutputImageType = TOutputImage;
  /** Pixel type of the projection (a float type for line integrals; integers hold gray levels). */
  using OutputPixelType = typename OutputImageType::PixelType;
  /** Region of the projection. */
  using OutputImageRegionType = typename OutputImageType::RegionType;
  /** The optional linear room -> volume transform. */
  using TransformType = Transform<double, 3, 3>;
  /** The projection geometry. */
  using GeometryType = DRRProjectionGeometry;
  /** Input value -> mu (1/mm). */
  using TransferFunctionType = DRRTransferFunction;
  /** What the output pixels hold. */
  using OutputModeEnum = PointBasedDRREnums::OutputMode;
  /** A label value (0 to 65535). */
  using LabelPixelType = DRRLabelSelection::LabelType;
  /** A list of labels. */
  using LabelListType = DRRLabelSelection::LabelListType;
  /** The label image: a label per voxel, on the volume's grid or resampled onto it by nearest neighbour. */
  using LabelImageType = Image<LabelPixelType, 3>;

  /** Dimension of the input volume: 3. */
  static constexpr unsigned int InputImageDimension = TInputImage::ImageDimension;
  /** Dimension of the output: 2, or 3 for a one-slice image placed in the room. */
  static constexpr unsigned int OutputImageDimension = TOutputImage::ImageDimension;
  static_assert(InputImageDimension == 3, "DRR filters take a 3D volume");
  static_assert(OutputImageDimension == 2 || OutputImageDimension == 3,
                "DRR filters write a 2D image or a 3D image with one slice");
  static_assert(std::is_arithmetic<InputPixelType>::value, "DRR filters take scalar voxels");
  /** Channel images: a line integral (dimensionless) per channel and pixel, on the projection's grid. */
  using ChannelImageType = VectorImage<float, OutputImageDimension>;

  ///@{
  /** The projection geometry. A default one (perspective, SAD 1000 mm, SID 1500 mm, 256 x 256 at 1 mm) exists. */
  itkSetObjectMacro(Geometry, GeometryType);
  itkGetModifiableObjectMacro(Geometry, GeometryType);
  ///@}

  ///@{
  /** Optional linear transform, room -> volume physical frame (null, the default: the identity). */
  itkSetConstObjectMacro(Transform, TransformType);
  itkGetConstObjectMacro(Transform, TransformType);
  ///@}

  /** Input value -> mu (1/mm). Default: natural, 60 keV. Held by the filter's preprocessing stage (not used with
   * SetAttenuationVolume(), whose stage has its own). */
  void
  SetTransferFunction(TransferFunctionType * transfer)
  {
    m_AttenuationVolumeFilter->SetTransferFunction(transfer);
  }
  /** The transfer function. */
  TransferFunctionType *
  GetTransferFunction()
  {
    return m_AttenuationVolumeFilter->GetTransferFunction();
  }
  /** The transfer function. */
  const TransferFunctionType *
  GetTransferFunction() const
  {
    return m_AttenuationVolumeFilter->GetTransferFunction();
  }

  ///@{
  /** What the output pixels hold: LineIntegral (default), Transmission, Gray8 or Gray16. */
  itkSetEnumMacro(OutputMode, OutputModeEnum);
  itkGetConstMacro(OutputMode, OutputModeEnum);
  ///@}

  ///@{
  /** Centre of the gray-level window (Gray8, Gray16), line-integral units (dimensionless). Default 0; not used while
   * the width is 0. */
  itkSetMacro(WindowLevel, double);
  itkGetConstMacro(WindowLevel, double);
  ///@}
  ///@{
  /** Width of the gray-level window, line-integral units. 0 (the default) or less: the automatic window, from the
   * image's 0.5th to its 99.5th percentile (DRROutputConversion::ComputeAutomaticWindow(), pbdrr's rule too). */
  itkSetMacro(WindowWidth, double);
  itkGetConstMacro(WindowWidth, double);
  ///@}

  ///@{
  /** Optional label image (docs/design.md section 13): a label (0 to 65535) per voxel, on the volume's grid (size,
   * origin, spacing, direction), or else resampled onto it by nearest neighbour (0 outside it), with a warning; one
   * that covers no voxel of the volume is refused at Update(). */
  itkSetInputMacro(LabelImage, LabelImageType);
  itkGetInputMacro(LabelImage, LabelImageType);
  ///@}
  /** Only voxels of these labels attenuate (empty, the default: every label). Each must be in the label image. */
  void
  SetKeptLabels(const LabelListType & labels)
  {
    m_AttenuationVolumeFilter->SetKeptLabels(labels);
  }
  /** The kept labels (empty: every label). */
  const LabelListType &
  GetKeptLabels() const
  {
    return m_AttenuationVolumeFilter->GetKeptLabels();
  }
  /** Voxels of these labels do not attenuate (default none). Each must be in the label image. */
  void
  SetDroppedLabels(const LabelListType & labels)
  {
    m_AttenuationVolumeFilter->SetDroppedLabels(labels);
  }
  /** The dropped labels. */
  const LabelListType &
  GetDroppedLabels() const
  {
    return m_AttenuationVolumeFilter->GetDroppedLabels();
  }
  ///@{
  /** Label channels (default off): one line-integral image per attenuating label, in increasing label order, from
   * the same render (GetChannelOutput()). Their sum is the projection (for the point-based filter, its fixed-point
   * sums are the projection's, exactly). Needs a label image. */
  void
  SetLabelChannels(bool channels)
  {
    m_AttenuationVolumeFilter->SetLabelChannels(channels);
  }
  bool
  GetLabelChannels() const
  {
    return m_AttenuationVolumeFilter->GetLabelChannels();
  }
  itkBooleanMacro(LabelChannels);
  ///@}
  ///@{
  /** Material channels (default off; docs/design.md section 14): with the transfer function's Materials mode, one
   * line-integral image of mu at the reference energy per material of its table (channel m: material m), the input of
   * DRRPolychromaticImageFilter. Not together with LabelChannels. */
  void
  SetMaterialChannels(bool channels)
  {
    m_AttenuationVolumeFilter->SetMaterialChannels(channels);
  }
  bool
  GetMaterialChannels() const
  {
    return m_AttenuationVolumeFilter->GetMaterialChannels();
  }
  itkBooleanMacro(MaterialChannels);
  ///@}
  /** The labels of the channels of the attenuation model rendered, in channel order (empty without channels). */
  const LabelListType &
  GetChannelLabels() const;
  /** The channel images of the last update with LabelChannels on: a component per channel (GetChannelLabels()), line
   * integrals (dimensionless) whatever the output mode; an empty image otherwise. */
  ChannelImageType *
  GetChannelOutput();
  /** The covariance of the channels' estimates per pixel (dimensionless^2): K (K + 1) / 2 components, the upper
   * triangle row major, (0, 0), (0, 1), ..., (K - 1, K - 1); zero for the exact filter. */
  ChannelImageType *
  GetChannelCovarianceOutput();

  /** A shared attenuation model (optional): the output of a DRRImageToAttenuationVolumeFilter that other filters
   * render too, in place of the input volume (not both); the pipeline updates it. Its stage holds the transfer function
   * and the labels: this filter's are not used, and a label image or label setting on it is refused. */
  itkSetInputMacro(AttenuationVolume, DRRAttenuationVolume);

  ///@{
  /** Streaming (issue 30, docs/design.md section 16): the volume is read and rendered in this many slabs of whole z
   * planes (its slowest axis), each requested from the pipeline in turn (ITK's requested regions: a streaming reader,
   * as MetaImage's, NRRD's or uncompressed NIfTI's, reads only that slab), so that the render holds one slab and its
   * attenuation model at a time. The projection is the sum of the slabs' (each filter says how exactly). 1 (the
   * default) reads the whole volume at once; a filter may round slabs to whole blocks of planes, and makes at most one
   * slab per block. The filter's preprocessing stage models each slab (its voxels, labels and materials); labels
   * and channels stream (label channels numbered by the labels of the whole label image, read whole), a shared
   * attenuation volume does not. */
  itkSetClampMacro(NumberOfStreamDivisions, unsigned int, 1, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfStreamDivisions, unsigned int);
  ///@}

  ///@{
  /** Memory budget, bytes: a volume whose unstreamed render would hold more (GetBytesPerVoxel() per voxel) is
   * streamed in as many slabs as bring each within it, NumberOfStreamDivisions at least. Default:
   * half the machine's physical memory (DRRMemoryBudget); 0: no budget (streamed only when asked). */
  itkSetMacro(MemoryBudget, uint64_t);
  itkGetConstMacro(MemoryBudget, uint64_t);
  ///@}

  /** Slabs the volume is streamed in: NumberOfStreamDivisions, or more for the memory budget (if the settings can be
   * streamed), at most one per block of GetSlabAlignment() planes; 1: not streamed. Needs the input's information
   * (its largest region). */
  unsigned int
  GetNumberOfSlabs() const;

  /** While streaming, the slab being read, 1 to GetNumberOfSlabs() (for progress: a render may pass over the slabs
   * more than once): the one the preprocessing stage was last asked for; 0 otherwise. */
  unsigned int
  GetCurrentSlab() const;

  /** Why the filter's settings cannot be streamed, empty if they can: a budget streams only what can be, and
   * NumberOfStreamDivisions > 1 with settings that cannot is refused with this reason. The base's: no shared
   * attenuation volume (it is whole already). Labels and channels stream: every slab's model numbers its channels as
   * the whole volume's (the materials of the table, the labels of the whole label image). Public, and asked of the
   * settings alone (no input is needed), so that a program asks a configured filter before it reads the volume. */
  virtual std::string
  WhyNotStreamable() const;

  /** Bytes per voxel an unstreamed render holds: the input pixel and, as measured on the chest x2 and x4
   * (docs/performance.md), the filter's tables. */
  virtual double
  GetBytesPerVoxel() const
  {
    return sizeof(InputPixelType);
  }

  /** The attenuation model rendered: the shared one, or the output of the filter's own stage, brought up to date now
   * (ITK's pipeline: built only if its inputs or settings changed). */
  const DRRAttenuationVolume *
  GetAttenuationVolume();

  /** Includes the geometry, transform and the preprocessing stage's settings (transfer function, labels). */
  ModifiedTimeType
  GetMTime() const override;

protected:
  DRRImageFilterBase();
  ~DRRImageFilterBase() override = default;

  /** Output size, spacing, origin and direction from the geometry (see DRRProjectionGeometry). */
  void
  GenerateOutputInformation() override;
  /** Requests the whole input (any voxel may project anywhere), or when streaming its first slab (the others are
   * requested slab by slab while the filter renders). */
  void
  GenerateInputRequestedRegion() override;
  /** Generates the whole output: every point may land on any pixel. */
  void
  EnlargeOutputRequestedRegion(DataObject * output) override;
  /** Input and output live in different spaces: nothing to compare. */
  void
  VerifyInputInformation() const override
  {}
  /** The rules of the inputs and outputs, checked before every update: an input volume or a shared attenuation model
   * (one of them), no label settings beside a shared model, an output mode the output pixel type holds, and for
   * streaming settings that stream (WhyNotStreamable()). */
  void
  VerifyPreconditions() const override;

  /** False if the next streamed update reads no slab (the point filter's kept points drawn already): the input is
   * then asked for what it holds, not for a slab. */
  virtual bool
  ReadsSlabsAtNextUpdate() const
  {
    return true;
  }

  /** Planes a slab of a streamed render starts at a multiple of (1: any plane; the point-based filter's bricks and
   * coarse blocks need more). */
  virtual uint64_t
  GetSlabAlignment() const
  {
    return 1;
  }
  /** Slab number `slab` of the input's largest region: whole z planes, the blocks of planes shared out evenly. */
  typename InputImageType::RegionType
  GetSlabRegion(unsigned int slab) const;
  /** The attenuation model of slab `slab`, from the filter's preprocessing stage asked for that region (a streaming
   * reader reads it alone; an image in memory is already there): its index-to-physical matrix the volume's, its origin
   * the slab's first plane, 16-bit values read in place, the slab's labels applied. It is the stage's output, which
   * holds one slab: the next ReadSlab() builds the next slab in it, after freeing this one's voxels (drop what was
   * derived from it first). */
  DRRAttenuationVolume::Pointer
  ReadSlab(unsigned int slab);
  /** The newest modified time of what the attenuation model is made of: the preprocessing stage's settings and
   * transfer function, and the input's and the label image's pipelines (for data made by a source, the source's time:
   * their own changes with every slab read). Whatever is drawn from the model is stale once this is newer. */
  ModifiedTimeType
  GetModelMadeOfTime() const;
  /** A model of no voxels with the whole input's grid (index-to-physical matrix and first voxel), for the whole
   * volume's projection without reading it. */
  DRRAttenuationVolume::Pointer
  MakeInputGrid() const;

  /** The affine map of the transform (identity without one); throws for a non-linear transform. */
  void
  ComputeTransformAffine(DRRPointProjection::MatrixType & matrix, DRRPointProjection::VectorType & offset) const;

  /** The projection mapping for the current geometry, volume and transform. */
  DRRPointProjection
  MakeProjection();
  /** The projection mapping of the current geometry and transform onto the grid of volume (a slab's, when streaming).
   */
  DRRPointProjection
  MakeProjection(const DRRAttenuationVolume & volume) const;

  /** Converts a line-integral image to the output mode and writes it into output 0. With a standard-error image,
   * also writes output 1: the standard error of the output values, carried through the output mode by the delta
   * method (times exp(-L) for transmission; times levels per unit of L inside the gray window, 0 where clamped). */
  void
  WriteOutputs(const std::vector<double> & lineIntegral, const std::vector<double> * standardError = nullptr);

  /** Writes the channel outputs: K line integrals per pixel (pixel major) and, if not null, K (K + 1) / 2 covariance
   * entries per pixel (zero if null). Leaves both empty (no components) without channels. */
  void
  WriteChannelOutputs(const std::vector<double> & channels, const std::vector<double> * covariance);

  /** The indexed outputs' MakeOutput(idx), beside the named one below. */
  using Superclass::MakeOutput;
  /** Makes the channel outputs (named "Channels" and "ChannelCovariance"); other names as the superclass does. */
  DataObject::Pointer
  MakeOutput(const ProcessObject::DataObjectIdentifierType & name) override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** The preprocessing stage. */
  using AttenuationVolumeFilterType = DRRImageToAttenuationVolumeFilter<InputImageType>;

  OutputPixelType *
  AllocateOutput(unsigned int index, size_t numberOfPixels);
  /** The shared attenuation model, or null. */
  const DRRAttenuationVolume *
  GetSharedAttenuationVolume() const;
  /** The filter's own preprocessing stage, given the filter's input, label image and work units. */
  AttenuationVolumeFilterType *
  ConnectStage();
  /** The first plane of slab `slab` of `slabs`, and the end of its planes, counted from the largest region's first. */
  void
  GetSlabPlanes(unsigned int slab, unsigned int slabs, uint64_t & first, uint64_t & end) const;

  typename GeometryType::Pointer                m_Geometry;
  typename TransformType::ConstPointer          m_Transform;
  OutputModeEnum                                m_OutputMode{ OutputModeEnum::LineIntegral };
  double                                        m_WindowLevel{ 0.0 };
  double                                        m_WindowWidth{ 0.0 };
  unsigned int                                  m_NumberOfStreamDivisions{ 1 };
  uint64_t                                      m_MemoryBudget{ DRRMemoryBudget::GetDefaultBudgetInBytes() };
  typename AttenuationVolumeFilterType::Pointer m_AttenuationVolumeFilter; // the filter's own preprocessing stage
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkDRRImageFilterBase.hxx"
#endif

#endif
