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
#ifndef itkDRRImageToAttenuationVolumeFilter_h
#define itkDRRImageToAttenuationVolumeFilter_h

#include "itkDRRCompatibility.h"
#include "itkDRRAttenuationVolume.h"
#include "itkDRRImageFileIntegrity.h"
#include "itkDRRLabelSelection.h"
#include "itkDRRTransferFunction.h"
#include "itkImage.h"
#include "itkProcessObject.h"

#include <string>

namespace itk
{
/** \class DRRImageToAttenuationVolumeFilter
 * \brief The preprocessing stage of the DRR filters: a CT volume (and an optional label image) in, the attenuation
 * model they render out (DRRAttenuationVolume, mu in 1/mm on the volume's grid).
 *
 * A process object of ITK's pipeline: it runs when its input, label image, transfer function or label settings
 * changed since its last run (ITK decides from the modified times), and not otherwise. Every DRR filter builds one of
 * its own when it is given none; given one's output (DRRImageFilterBase::SetAttenuationVolume()), several filters share
 * one model, built once, as a registration rendering points and exact rays of one CT does:
 *
 * \code
 *   auto model = itk::DRRImageToAttenuationVolumeFilter<CTImageType>::New();
 *   model->SetInput(ct);
 *   points->SetAttenuationVolume(model->GetOutput());
 *   exact->SetAttenuationVolume(model->GetOutput());
 * \endcode
 *
 * - Input: a 3D scalar image (HU, or mu in 1/mm with an Identity transfer function); its origin, spacing and
 *   direction become the model's index-to-physical mapping. A 16-bit input is read in place (the model references its
 *   pixel container). NaN or infinite voxels and negative attenuation are refused. An input read from a file is
 *   checked first for being cut or damaged (VerifyInputFile()).
 * - Slabs (streaming, docs/design.md section 16): the model is of the output's requested region
 *   (DRRAttenuationVolume::SetRequestedRegion(); the whole volume by default), whole z planes of the input, which is
 *   asked for those planes alone: a streaming reader reads them alone. The slab's model has the volume's
 *   index-to-physical matrix and its origin at the slab's first plane; its voxels, labels and materials are those of
 *   the whole volume's model. Only one slab is held: the last one's model is released before the next is read.
 * - Labels (optional, docs/design.md section 13): a label image on the volume's grid, or one resampled onto it by
 *   ITK's ResampleImageFilter with a nearest-neighbour interpolator (label 0 outside it, with a warning), selects which
 *   voxels attenuate (SetKeptLabels(), SetDroppedLabels()) and, with LabelChannels on, gives every voxel its label's
 *   channel. A slab takes the label image's matching planes (on the volume's grid) or the resampled labels of its own
 *   voxels; a kept or dropped label must be in some slab, which is checked when the slabs read in order reach the last
 *   plane. Label channels need the whole volume (a slab's channels would be its own labels).
 * - Material channels (docs/design.md section 14): with the transfer function's Materials mode, every voxel's channel
 *   is its material.
 *
 * \sa DRRAttenuationVolume, DRRImageFilterBase, DRRTransferFunction, DRRLabelSelection
 * \ingroup PointBasedDRR
 */
template <typename TInputImage>
class ITK_TEMPLATE_EXPORT DRRImageToAttenuationVolumeFilter : public ProcessObject
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRImageToAttenuationVolumeFilter);

  /** Standard class type aliases. */
  using Self = DRRImageToAttenuationVolumeFilter;
  using Superclass = ProcessObject;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRImageToAttenuationVolumeFilter);

  /** The 3D volume: HU, or mu in 1/mm (any scalar pixel type). */
  using InputImageType = TInputImage;
  /** Voxel type of the volume. */
  using InputPixelType = typename InputImageType::PixelType;
  /** The output: the attenuation model. */
  using OutputType = DRRAttenuationVolume;
  /** Input value -> mu (1/mm). */
  using TransferFunctionType = DRRTransferFunction;
  /** A label value (0 to 65535). */
  using LabelPixelType = DRRLabelSelection::LabelType;
  /** A list of labels. */
  using LabelListType = DRRLabelSelection::LabelListType;
  /** The label image: a label per voxel. */
  using LabelImageType = Image<LabelPixelType, 3>;

  static_assert(InputImageType::ImageDimension == 3, "the attenuation model is made of a 3D volume");
  static_assert(std::is_arithmetic<InputPixelType>::value, "the attenuation model is made of scalar voxels");

  /** Dimension of the input: 3. */
  static constexpr unsigned int InputImageDimension = 3;
  /** A region of the input's grid: the model's requested region, a slab of whole z planes. */
  using RegionType = typename InputImageType::RegionType;

  using Superclass::SetInput;
  /** The volume (required). */
  virtual void
  SetInput(const InputImageType * input);
  /** The volume. */
  const InputImageType *
  GetInput() const;

  ///@{
  /** Optional label image: a label (0 to 65535) per voxel, on the volume's grid or resampled onto it. */
  itkSetInputMacro(LabelImage, LabelImageType);
  itkGetInputMacro(LabelImage, LabelImageType);
  ///@}

  /** The attenuation model. */
  OutputType *
  GetOutput();
  /** The attenuation model. */
  const OutputType *
  GetOutput() const;

  ///@{
  /** Input value -> mu (1/mm). Default: natural, 60 keV. */
  itkSetObjectMacro(TransferFunction, TransferFunctionType);
  itkGetModifiableObjectMacro(TransferFunction, TransferFunctionType);
  ///@}

  /** Only voxels of these labels attenuate (empty, the default: every label). Each must be in the label image. */
  void
  SetKeptLabels(const LabelListType & labels)
  {
    if (labels != m_KeptLabels)
    {
      m_KeptLabels = labels;
      this->Modified();
    }
  }
  /** The kept labels (empty: every label). */
  itkGetConstReferenceMacro(KeptLabels, LabelListType);
  /** Voxels of these labels do not attenuate (default none). Each must be in the label image. */
  void
  SetDroppedLabels(const LabelListType & labels)
  {
    if (labels != m_DroppedLabels)
    {
      m_DroppedLabels = labels;
      this->Modified();
    }
  }
  /** The dropped labels. */
  itkGetConstReferenceMacro(DroppedLabels, LabelListType);
  ///@{
  /** Label channels (default off): every attenuating label is a channel, in increasing label order. Needs a label
   * image. */
  itkSetMacro(LabelChannels, bool);
  itkGetConstMacro(LabelChannels, bool);
  itkBooleanMacro(LabelChannels);
  ///@}
  ///@{
  /** Material channels (default off): with the transfer function's Materials mode, channel m holds material m. Not
   * together with LabelChannels. */
  itkSetMacro(MaterialChannels, bool);
  itkGetConstMacro(MaterialChannels, bool);
  itkBooleanMacro(MaterialChannels);
  ///@}

  /** Includes the transfer function's. */
  ModifiedTimeType
  GetMTime() const override;

  /** Refuses, before anything is read, an input file that the reader upstream (an ImageFileReader, or any source with
   * a "FileName" input) would read cut or damaged (DRRImageFileIntegrity): NIfTI's and TIFF's readers fill what is
   * missing with zeros, and MetaImage's, asked for a slab, says so on std::cerr only. Once per file and reader time.
   * The stage calls it before it asks for its input; a filter that reads the same input itself first calls it too. */
  void
  VerifyInputFile();

  /** The region of labels that holds the labels of the voxels of input's region: the matching region if labels lie on
   * input's grid (a slab's planes), else the whole label image (resampled onto the slab by nearest neighbour). */
  static typename LabelImageType::RegionType
  LabelRegionOf(const InputImageType & input, const LabelImageType & labels, const RegionType & region);

  /** Gives volume the index-to-physical mapping of input's grid (direction times spacing) with its first voxel at
   * input's index firstVoxel (the largest region's first, or a streamed slab's). */
  static void
  SetIndexToPhysical(const InputImageType &                     input,
                     const typename InputImageType::IndexType & firstVoxel,
                     OutputType &                               volume);

protected:
  DRRImageToAttenuationVolumeFilter();
  ~DRRImageToAttenuationVolumeFilter() override = default;

  /** The indexed outputs' MakeOutput(name), beside the indexed one below. */
  using Superclass::MakeOutput;
  /** Makes a DRRAttenuationVolume. */
  DataObject::Pointer
  MakeOutput(DataObjectPointerArraySizeType index) override;

  /** Requests the model's region of the volume (the output's requested region) and the label image's matching
   * region (the whole image for label channels, which its labels number), after VerifyInputFile(); frees the input's
   * buffer first if its source makes the region anew (else the new slab would be allocated beside the last). */
  void
  GenerateInputRequestedRegion() override;
  /** The model's largest possible region: the input's. */
  void
  GenerateOutputInformation() override;
  /** The required input, and the settings' rules: label settings need a label image, material channels the
   * transfer function's Materials mode and no label channels. Throws an ExceptionObject naming the rule. */
  void
  VerifyPreconditions() const override;
  /** Builds the model of the requested region into the output, in place of the previous one (freed first). */
  void
  GenerateData() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** The first value of region (whole z planes of the largest possible region) in the input's buffer; throws if the
   * input's source did not buffer it in whole planes. */
  const InputPixelType *
  GetRegionValues(const InputImageType & input, const RegionType & region) const;
  /** Material channels: every voxel's material (transfer function's table) as its channel; values: the model's. */
  void
  ApplyMaterials(const InputPixelType * values, OutputType & volume);
  /** The label selection and label channels (DRRLabelSelection) of the voxels of region. */
  void
  ApplyLabels(const InputImageType & input, const RegionType & region, OutputType & volume);
  /** The labels of a slab (not the whole volume): masks the voxels of labels left out, and checks the labels present
   * in the slabs read in order from the first plane once they reach the last. */
  void
  ApplySlabLabels(const LabelPixelType * labels,
                  const RegionType &     region,
                  const RegionType &     largest,
                  OutputType &           volume);
  /** The label channels of a slab: numbered by the labels of the whole volume (GetWholeChannelLabels()), as the
   * whole volume's model numbers them, not by the slab's own. */
  void
  ApplySlabLabelChannels(const InputImageType & input,
                         const LabelPixelType * labels,
                         const RegionType &     region,
                         OutputType &           volume);
  /** The labels of the channels of the whole volume (the attenuating labels present in it), found once for the slabs:
   * again only if the labels, the input or the selection changed since. planes: the planes resampled at a time. */
  const LabelListType &
  GetWholeChannelLabels(const InputImageType & input, SizeValueType planes);
  /** The labels of region's voxels on the volume's grid: the label image itself, or its region's voxels resampled by
   * nearest neighbour (label 0 outside; the resampling warned of at the first plane unless warn is false). first is
   * set to the label of region's first voxel. */
  typename LabelImageType::ConstPointer
  LabelsOnVolumeGrid(const InputImageType &  input,
                     const RegionType &      region,
                     const LabelPixelType *& first,
                     bool                    warn = true) const;
  /** True if labels lie on input's grid (size, origin, spacing and direction, to a tolerance). */
  static bool
  IsOnVolumeGrid(const InputImageType & input, const LabelImageType & labels);
  /** Refuses, before resampling, a label image that no voxel centre of the volume can fall in (another volume's). */
  void
  VerifyLabelsCoverVolume(const InputImageType & input, const LabelImageType & labels) const;

  typename TransferFunctionType::Pointer m_TransferFunction;
  LabelListType                          m_KeptLabels;
  LabelListType                          m_DroppedLabels;
  bool                                   m_LabelChannels{ false };
  bool                                   m_MaterialChannels{ false };
  // Caches, not settings: the file VerifyInputFile() last passed and its reader's time then; the labels present in the
  // slabs modelled in order since the first plane, and the plane after them.
  std::string                       m_CheckedInputFile;
  ModifiedTimeType                  m_CheckedInputFileTime{ 0 };
  DRRLabelSelection::LabelFlagsType m_LabelsInSlabs;
  IndexValueType                    m_NextSlabPlane{ 0 };
  // The whole volume's channel labels for the slabs, and when they were found.
  LabelListType m_WholeChannelLabels;
  TimeStamp     m_WholeChannelLabelsTime;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkDRRImageToAttenuationVolumeFilter.hxx"
#endif

#endif
