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
#include "pbdrrApplication.h"
#include "pbdrrLabels.h"
#include "itkDRRPolychromaticImageFilter.h"
#include "pbdrrBatch.h"
#include "pbdrrMessages.h"
#include "pbdrrOutputFiles.h"
#include "pbdrrProgressBar.h"
#include "pbdrrRegistration.h"
#include "pbdrrView.h"
#include "pbdrrVolumeLoader.h"
#include "pbdrrVolumeFileReader.h"

#include "itkCommand.h"
#include "itkDRRMemoryBudget.h"
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkDRRQuantumNoiseImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkGDCMImageIO.h"
#include "itkDRROutputConversion.h"
#include "itkDRRSamplerFactory.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageIOFactory.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itkVersion.h"

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <sys/stat.h>
#include <type_traits>
#include <unistd.h>

namespace pbdrr
{
namespace
{
using Clock = std::chrono::steady_clock;

double
SecondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

} // namespace

itk::DRRTransferFunction::Pointer
MakeTransferFunction(const Options & options)
{
  auto transfer = itk::DRRTransferFunction::New();
  if (options.inputUnits == "mu")
  {
    transfer->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
  }
  if (options.energyKeV)
  {
    transfer->SetEffectiveEnergyInKeV(*options.energyKeV);
  }
  if (options.muWater)
  {
    transfer->SetMuWaterPerMillimeter(*options.muWater);
  }
  if (options.airThreshold)
  {
    transfer->SetAirThreshold(*options.airThreshold);
  }
  if (IsPolychromatic(options))
  {
    auto table = itk::DRRMaterialTable::New();
    if (options.materialsFile.empty())
    {
      table->SetDefault();
    }
    else
    {
      table->ReadFile(options.materialsFile);
    }
    transfer->SetMaterialTable(table);
  }
  return transfer;
}

bool
IsPolychromatic(const Options & options)
{
  return !options.spectrumFile.empty() || options.kvp.has_value();
}

bool
ReadsStandardError(const Options & options)
{
  return !options.standardErrorOutput.empty() || IsPolychromatic(options) || options.accuracyPercent.has_value();
}

itk::DRRXRaySpectrum::Pointer
MakeSpectrum(const Options & options)
{
  if (!IsPolychromatic(options))
  {
    return nullptr;
  }
  auto spectrum = itk::DRRXRaySpectrum::New();
  if (options.kvp)
  {
    spectrum->SetKramers(*options.kvp);
  }
  else
  {
    spectrum->ReadFile(options.spectrumFile);
  }
  return spectrum;
}

template <typename TVolume>
ProjectionType::ConstPointer
PolychromaticImage(const Options &                options,
                   const itk::DRRXRaySpectrum *   spectrum,
                   BaseFilterType<TVolume> *      filter,
                   ProjectionType::ConstPointer & standardError)
{
  if (!spectrum)
  {
    return filter->GetOutput();
  }
  using PolychromaticType =
    itk::DRRPolychromaticImageFilter<typename BaseFilterType<TVolume>::ChannelImageType, ProjectionType>;
  auto poly = PolychromaticType::New();
  poly->SetInput(filter->GetChannelOutput());
  poly->SetCovarianceInput(filter->GetChannelCovarianceOutput());
  poly->SetMaterialTable(filter->GetTransferFunction()->GetMaterialTable());
  poly->SetSpectrum(spectrum);
  poly->SetReferenceEnergyInKeV(filter->GetTransferFunction()->GetEffectiveEnergyInKeV());
  poly->SetCorrectJensenBias(options.jensenCorrection);
  poly->Update();
  standardError = poly->GetStandardErrorOutput();
  return poly->GetOutput();
}

template ProjectionType::ConstPointer
PolychromaticImage(const Options &,
                   const itk::DRRXRaySpectrum *,
                   BaseFilterType<HUVolumeType> *,
                   ProjectionType::ConstPointer &);
template ProjectionType::ConstPointer
PolychromaticImage(const Options &,
                   const itk::DRRXRaySpectrum *,
                   BaseFilterType<VolumeType> *,
                   ProjectionType::ConstPointer &);

namespace
{

template <typename TVolume>
std::string
Describe(const TVolume * volume)
{
  const auto         region = volume->GetLargestPossibleRegion();
  std::ostringstream s;
  s << "size " << region.GetSize()[0] << " x " << region.GetSize()[1] << " x " << region.GetSize()[2] << ", spacing "
    << volume->GetSpacing()[0] << " x " << volume->GetSpacing()[1] << " x " << volume->GetSpacing()[2] << " mm, origin "
    << volume->GetOrigin() << " mm, direction [";
  for (unsigned int r = 0; r < 3; ++r)
  {
    s << (r ? "; " : "") << volume->GetDirection()[r][0] << " " << volume->GetDirection()[r][1] << " "
      << volume->GetDirection()[r][2];
  }
  if (volume->GetBufferedRegion() != region)
  {
    s << "], values not read yet (streamed slab by slab)";
    return s.str();
  }
  const auto *   values = volume->GetBufferPointer();
  const uint64_t count = region.GetNumberOfPixels();
  if (count == 0)
  {
    s << "], no values (empty)"; // nothing to dereference: the checks that refuse an empty volume come later
    return s.str();
  }
  // A plain loop of min and max, which the compiler vectorizes (std::minmax_element, which keeps positions, is 5x
  // slower: 0.5 s on a 577 M voxel CT).
  auto lowest = values[0];
  auto highest = values[0];
  for (uint64_t v = 1; v < count; ++v)
  {
    lowest = values[v] < lowest ? values[v] : lowest;
    highest = highest < values[v] ? values[v] : highest;
  }
  s << "], values " << +lowest << " .. " << +highest << " (" << sizeof(*values) << " bytes per voxel)";
  return s.str();
}

std::string
DescribeGeometry(const itk::DRRProjectionGeometry * g)
{
  std::ostringstream s;
  const auto         number = [](double value) { return RoundedForDisplay(value); };
  s << itk::PointBasedDRREnums::GetName(g->GetProjection()) << ", SAD " << number(g->GetSourceToIsocenterDistance())
    << " mm, SID " << number(g->GetSourceToDetectorDistance()) << " mm, isocenter " << FormatTriple(g->GetIsocenter())
    << ", nrm " << FormatTriple(g->GetNormal()) << ", vup " << FormatTriple(g->GetViewUp()) << ", detector "
    << g->GetDetectorSize()[0] << " cols x " << g->GetDetectorSize()[1] << " rows at "
    << number(g->GetDetectorSpacing()[0]) << " x " << number(g->GetDetectorSpacing()[1]) << " mm, offset "
    << number(g->GetDetectorOffset()[0]) << " " << number(g->GetDetectorOffset()[1]) << " mm; source "
    << FormatTriple(g->GetSourcePosition()) << ", columns along " << FormatTriple(g->GetColumnDirection())
    << ", rows along " << FormatTriple(g->GetRowDirection());
  return s.str();
}

} // namespace

template <typename TVolume>
Renderer<TVolume>
MakeRenderer(const Options & options, const TVolume * volume)
{
  Renderer<TVolume> renderer;
  if (!options.exact)
  {
    auto pointBased = PointFilterType<TVolume>::New();
    pointBased->SetNumberOfSamples(options.samples);
    pointBased->SetSeed(options.seed);
    pointBased->SetNumberOfStrata(options.strata);
    pointBased->SetReconstructionKernel(options.kernel);
    pointBased->SetSplat(options.splat);
    pointBased->SetPointWeighting(options.paperCount ? itk::PointBasedDRREnums::PointWeighting::PaperCount
                                                     : itk::PointBasedDRREnums::PointWeighting::Unbiased);
    pointBased->SetSampler(itk::DRRSamplerFactory::Create(options.sampler, options.paperCount));
    pointBased->SetControlVariateFactor(options.controlVariate);
    pointBased->SetControlVariateRaysPerSide(options.raysPerSide);
    // The standard error only where it is read: computing it changes the estimate (the control variate's coarse image
    // then traces two replicates of rays, not one), so a single view and view 0 of a batch, which reads none, would
    // otherwise be two estimates of the same image (issue 28).
    pointBased->SetComputeStandardError(ReadsStandardError(options));
    pointBased->SetTargetError(options.accuracyPercent ? *options.accuracyPercent / 100.0 : 0.0);
    // The estimator is chosen for the accuracy unless the points were (--samples, --control-variate).
    pointBased->SetChooseEstimator(options.accuracyPercent && !IsGiven(options, "--samples") &&
                                   !options.controlVariateGiven);
    renderer.Points = pointBased;
    renderer.Filter = pointBased.GetPointer();
  }
  else
  {
    auto exact = itk::ExactDRRImageFilter<TVolume, ProjectionType>::New();
    exact->SetReconstructionKernel(*options.exact);
    exact->SetRaysPerPixelSide(options.raysPerSide);
    renderer.Filter = exact.GetPointer();
  }
  // The filter decides the slabs (GetNumberOfSlabs()): --stream at least, more if the budget needs them.
  renderer.Filter->SetNumberOfStreamDivisions(options.stream);
  if (options.memoryBudget)
  {
    renderer.Filter->SetMemoryBudget(*options.memoryBudget);
  }
  renderer.Filter->SetInput(volume);
  renderer.Filter->SetTransferFunction(MakeTransferFunction(options));
  ApplyLabelOptions(options, renderer.Filter.GetPointer());
  renderer.Filter->SetMaterialChannels(IsPolychromatic(options));
  if (options.threads > 0)
  {
    renderer.Filter->SetNumberOfWorkUnits(options.threads);
  }
  if (options.accuracyIsDefault && renderer.Points && volume && renderer.Filter->GetNumberOfSlabs() > 1)
  {
    // A CT over the memory budget streams points (exact rays need it whole): the default's 10^7 points, rendered once
    // rather than refined, each pass of which would read the CT again.
    renderer.Points->SetTargetError(0.0);
    renderer.Points->SetChooseEstimator(false);
  }
  return renderer;
}

template Renderer<HUVolumeType>
MakeRenderer(const Options &, const HUVolumeType *);
template Renderer<VolumeType>
MakeRenderer(const Options &, const VolumeType *);

template <typename TVolume>
void
VerifyRenderSettings(const Options & options, const Renderer<TVolume> & renderer)
{
  try
  {
    if (renderer.Points)
    {
      renderer.Points->VerifySettings();
    }
  }
  catch (const itk::ExceptionObject & e)
  {
    throw UsageError(CleanMessage(e.GetDescription()));
  }
  const std::string why = options.stream > 1 ? renderer.Filter->WhyNotStreamable() : std::string();
  if (!why.empty())
  {
    throw UsageError("--stream " + std::to_string(options.stream) + ": " + why);
  }
}

template void
VerifyRenderSettings(const Options &, const Renderer<HUVolumeType> &);
template void
VerifyRenderSettings(const Options &, const Renderer<VolumeType> &);

template <typename TVolume>
unsigned int
AnnounceSlabs(const Options & options, const Renderer<TVolume> & renderer)
{
  const unsigned int slabs = renderer.Filter->GetNumberOfSlabs();
  if (slabs > 1 && options.stream <= 1 && !options.quiet)
  {
    std::cerr << "pbdrr: the render of " << options.input << " would hold more than the memory budget ("
              << static_cast<double>(renderer.Filter->GetMemoryBudget()) / 0x1p30
              << " GiB, --memory-budget): streamed in " << slabs << " slabs" << std::endl;
  }
  return slabs;
}

template unsigned int
AnnounceSlabs(const Options &, const Renderer<HUVolumeType> &);
template unsigned int
AnnounceSlabs(const Options &, const Renderer<VolumeType> &);

ProjectionType::ConstPointer
AddQuantumNoise(const Options & options, const ProjectionType * image, uint64_t seed)
{
  if (!options.photons)
  {
    return image;
  }
  auto noise = itk::DRRQuantumNoiseImageFilter<ProjectionType>::New();
  noise->SetInput(image);
  noise->SetNumberOfPhotons(*options.photons);
  noise->SetSeed(seed);
  noise->Update();
  return noise->GetOutput();
}

std::string
VersionText()
{
  return "pbdrr (PointBasedDRR) 0.1.0, ITK " + std::string(itk::Version::GetITKVersion());
}

namespace
{
/** pbdrr -v's account of what the render holds per voxel of the CT, beyond the CT itself, and what its preprocessing
 * cost per voxel: the scale the paper promises is a cost set by the points, not by the CT. */
template <typename TVolume>
std::string
DescribeMemory(const TVolume *            volume,
               BaseFilterType<TVolume> *  filter,
               PointFilterType<TVolume> * pointBased,
               double                     preprocessSeconds)
{
  const double       voxels = static_cast<double>(volume->GetLargestPossibleRegion().GetNumberOfPixels());
  std::ostringstream s;
  s << std::setprecision(3) << "bytes per voxel: the CT " << sizeof(typename TVolume::PixelType);
  if (volume->GetBufferedRegion() != volume->GetLargestPossibleRegion())
  {
    return s.str() + ", held one slab at a time (streamed)";
  }
  s << ", attenuation model " << filter->GetAttenuationVolume()->GetBytesPerVoxel();
  if (pointBased)
  {
    s << ", sampler tables " << static_cast<double>(pointBased->GetSampler()->GetTableSizeInBytes()) / voxels;
    if (const itk::DRRControlVariate * split = pointBased->GetControlVariate())
    {
      s << ", control variate " << static_cast<double>(split->GetTableSizeInBytes()) / voxels;
    }
  }
  s << "; preprocess " << 1e9 * preprocessSeconds / voxels << " ns per voxel";
  return s.str();
}

} // namespace

/** `--stream`: the CT's file opened, its header read, no voxel: the exact filter requests it slab by slab. A file whose
 * pixel type an int16 holds (8- or 16-bit signed, 8-bit unsigned) is read as int16 HU, any other as float, as
 * LoadVolume() reads it. A DICOM series (a directory) is refused: ITK reads a series whole. A cut or damaged file is
 * refused by the filters before their first slab (DRRImageFilterBase checks the file of the reader upstream). */
LoadedVolume
OpenStreamedVolume(const std::string & input)
{
  struct stat status;
  if (stat(input.c_str(), &status) != 0)
  {
    throw std::runtime_error("input " + input + " does not exist");
  }
  if (S_ISDIR(status.st_mode))
  {
    throw UsageError("--stream reads a MetaImage, NRRD or NIfTI file slab by slab, not a DICOM series (" + input +
                     " is a directory)");
  }
  auto io = itk::ImageIOFactory::CreateImageIO(input.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode);
  if (!io)
  {
    RefuseDamagedImageFile(input); // a header cut before ITK can tell the format: say so
    throw std::runtime_error("no ITK image reader reads " + input);
  }
  try
  {
    io->SetFileName(input);
    io->ReadImageInformation();
  }
  catch (const itk::ExceptionObject &)
  {
    RefuseDamagedImageFile(input); // a cut header: the check's words rather than the reader's
    throw;
  }
  if (io->GetNumberOfDimensions() != 3 || io->GetNumberOfComponents() != 1)
  {
    throw std::runtime_error(input + " is not a 3D scalar volume");
  }
  using Component = itk::IOComponentEnum;
  const auto   type = io->GetComponentType();
  LoadedVolume loaded;
  loaded.Description = input + " (streamed)";
  if (type == Component::CHAR || type == Component::SHORT || type == Component::UCHAR)
  {
    auto reader = itk::ImageFileReader<HUVolumeType>::New();
    reader->SetFileName(input);
    reader->UpdateOutputInformation();
    loaded.Set(HUVolumeType::Pointer(reader->GetOutput()));
    loaded.Source = reader;
  }
  else
  {
    auto reader = itk::ImageFileReader<VolumeType>::New();
    reader->SetFileName(input);
    reader->UpdateOutputInformation();
    loaded.Set(VolumeType::Pointer(reader->GetOutput()));
    loaded.Source = reader;
  }
  return loaded;
}

LoadedVolume
OpenVolumeHeader(const Options & options)
{
  struct stat status;
  if (stat(options.input.c_str(), &status) != 0 || S_ISDIR(status.st_mode))
  {
    return {};
  }
  auto io = itk::ImageIOFactory::CreateImageIO(options.input.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode);
  if (!io || dynamic_cast<itk::GDCMImageIO *>(io.GetPointer()))
  {
    return {}; // not an image ITK reads (the load says so), or DICOM: read whole
  }
  try
  {
    return OpenStreamedVolume(options.input);
  }
  catch (const std::exception &)
  {
    return {}; // the load words what is wrong with the file, after the settings' checks
  }
}

LoadedVolume
LoadVolumeAfterHeader(const Options &      options,
                      const LoadedVolume & header,
                      bool                 streamed,
                      const LoadProgress & progress)
{
  if (!streamed)
  {
    return LoadVolume(options.input, options.seriesUID, progress);
  }
  // --stream of what OpenVolumeHeader() did not open: a DICOM file, or OpenStreamedVolume()'s refusal.
  return header.IsSet() ? header : OpenStreamedVolume(options.input);
}

namespace
{
/** Renders and writes the view of the options from a loaded volume (of its own pixel type: int16 HU or float), with
 * the renderer given that volume and the view's geometry. */
template <typename TVolume>
void
RenderView(const Options &                               options,
           const LoadedVolume &                          loaded,
           const TVolume *                               volume,
           const Renderer<TVolume> &                     renderer,
           itk::DRRProjectionGeometry *                  geometry,
           const itk::DRRXRaySpectrum *                  spectrum,
           std::vector<std::pair<std::string, double>> & stages)
{
  const bool               chatty = !options.quiet;
  std::vector<std::string> notes;
  if (!options.projectionMatrixFile.empty())
  {
    CheckDetectorBeyondVolume(geometry, volume, 0.0, "--projection-matrix (--spacing DU)");
  }
  if (options.verbose)
  {
    std::cerr << "pbdrr: input: " << loaded.Description << "\npbdrr: volume: " << Describe(volume)
              << "\npbdrr: geometry: " << DescribeGeometry(geometry) << std::endl;
  }

  BaseFilterType<TVolume> *  filter = renderer.Filter;
  PointFilterType<TVolume> * pointBased = renderer.Points;
  filter->SetGeometry(geometry);

  auto start = Clock::now();
  if (filter->GetNumberOfSlabs() > 1)
  {
    // Streamed: each slab's model is built as the slab is read, in the render.
  }
  else if (pointBased)
  {
    pointBased->PrepareSampling();
  }
  else
  {
    filter->GetAttenuationVolume();
  }
  stages.emplace_back("preprocess", SecondsSince(start));

  ProgressBar progress(chatty);
  auto        command = itk::CStyleCommand::New();
  command->SetClientData(&progress);
  command->SetCallback([](itk::Object * caller, const itk::EventObject &, void * data) {
    const auto *      renderer = static_cast<BaseFilterType<TVolume> *>(caller);
    const std::string slab = renderer->GetCurrentSlab() > 0 ? " slab " + std::to_string(renderer->GetCurrentSlab()) +
                                                                " of " + std::to_string(renderer->GetNumberOfSlabs())
                                                            : std::string();
    static_cast<ProgressBar *>(data)->Show(renderer->GetProgress(), slab);
  });
  filter->AddObserver(itk::ProgressEvent(), command);
  start = Clock::now();
  filter->Update();
  progress.Finish();
  stages.emplace_back(!options.exact ? "sample+project" : "exact projection", SecondsSince(start));
  const ProjectionType * image = filter->GetOutput();
  if (chatty && std::all_of(image->GetBufferPointer(),
                            image->GetBufferPointer() + image->GetBufferedRegion().GetNumberOfPixels(),
                            [](float v) { return v == 0.0f; }))
  {
    std::cerr << "pbdrr: warning: the image is empty: the volume is all air or does not project onto the detector "
                 "(check --isocenter, --gantry/--nrm, --offset and --size)"
              << std::endl;
  }

  start = Clock::now();
  ProjectionType::ConstPointer       standardError = pointBased ? pointBased->GetStandardErrorOutput() : nullptr;
  const ProjectionType::ConstPointer lineIntegral = PolychromaticImage(options, spectrum, filter, standardError);
  // Seeded as view 0 of a batch is (a function of (seed, k) alone), so that a single view is view 0 of any batch.
  const ProjectionType::ConstPointer counted = AddQuantumNoise(options, lineIntegral, ViewSeed(options.seed, 0));
  WriteOutputs(
    options, counted, pointBased && !options.standardErrorOutput.empty() ? standardError.GetPointer() : nullptr, notes);
  WriteLabelChannels(options, filter);
  const std::string geometryPath = WriteGeometryBeside(options.output, geometry);
  stages.emplace_back("write", SecondsSince(start));

  if (options.verbose)
  {
    if (pointBased)
    {
      std::cerr << "pbdrr: sampler " << options.sampler << ", samples " << options.samples << ", seed " << options.seed
                << ", kernel " << itk::PointBasedDRREnums::GetName(options.kernel) << ", splat "
                << itk::PointBasedDRREnums::GetName(options.splat) << ", attenuation mass M "
                << pointBased->GetTotalMass() << " mm^2, points on the detector " << pointBased->GetPointsOnDetector()
                << std::endl;
      if (options.accuracyPercent && pointBased->GetTargetError() > 0.0)
      {
        PrintAccuracy(*pointBased, *options.accuracyPercent);
        if (options.accuracyIsDefault)
        {
          std::cerr << "pbdrr: accuracy: " << *options.accuracyPercent
                    << "% is pbdrr's default (--accuracy, --samples or --exact set the effort by hand)" << std::endl;
        }
      }
      if (const itk::DRRControlVariate * split = pointBased->GetControlVariate())
      {
        // M_r as the sampler of the residual summed it: the split's own sum would be another pass over the CT.
        const double residualMass = pointBased->GetSampler()->GetTotalMass();
        std::cerr << "pbdrr: control variate F " << split->GetFactor() << ": residual mass M_r " << residualMass
                  << " mm^2, M_r / M " << residualMass / split->GetTotalMass() << ", coarse image "
                  << (pointBased->GetComputeStandardError() ? 2 : 1) << " x " << options.raysPerSide << " x "
                  << options.raysPerSide << " antithetic ray pairs per pixel" << std::endl;
      }
      const std::string statistics = pointBased->GetSampler()->GetStatisticsSummary();
      if (!statistics.empty())
      {
        std::cerr << "pbdrr: " << options.sampler << ": " << statistics << std::endl;
      }
    }
    for (const auto & note : notes)
    {
      std::cerr << "pbdrr: " << note << std::endl;
    }
    std::cerr << "pbdrr: " << DescribeMemory(volume, filter, pointBased, stages[1].second) << std::endl;
    std::cerr << "pbdrr: time:";
    for (const auto & stage : stages)
    {
      std::cerr << " " << stage.first << " " << std::fixed << std::setprecision(3) << stage.second << " s;";
    }
    std::cerr << std::endl;
  }
  if (chatty)
  {
    std::cerr << "pbdrr: wrote " << options.output
              << (options.standardErrorOutput.empty() ? "" : " and " + options.standardErrorOutput) << ", its view in "
              << geometryPath << std::endl;
  }
}
/** The single view: its geometry and the filter that renders it built once, before the load, from the CT's header
 * (headerVolume; null for a DICOM series, whose values decide its pixel type as it is read), and asked whether their
 * settings hold; then the CT, read whole or, if the filter reads it in slabs, left to the filter. */
template <typename TVolume>
void
LoadAndRenderView(const Options &                               options,
                  const LoadedVolume &                          header,
                  const TVolume *                               headerVolume,
                  const itk::DRRXRaySpectrum *                  spectrum,
                  std::vector<std::pair<std::string, double>> & stages)
{
  // The view's checks (geometry file, SID against SAD) before the load; its isocenter the CT's centre if its header
  // is read.
  itk::DRRProjectionGeometry::Pointer geometry = MakeGeometry(options, headerVolume);
  const Renderer<TVolume>             renderer = MakeRenderer(options, headerVolume);
  VerifyRenderSettings(options, renderer);
  if (!headerVolume)
  {
    renderer.Filter->SetMemoryBudget(0); // a DICOM series is read whole: no budget streams it
  }
  renderer.Filter->SetGeometry(geometry);
  // --stream reads the file through its reader even where the filter makes one slab of it, as it always has.
  const bool fromHeader = AnnounceSlabs(options, renderer) > 1 || options.stream > 1;

  const bool         chatty = !options.quiet;
  auto               start = Clock::now();
  ProgressBar        loadProgress(chatty);
  const LoadedVolume loaded = LoadVolumeAfterHeader(options, header, fromHeader, [&](size_t done, size_t total) {
    loadProgress.ShowCount("reading DICOM files", done, total);
  });
  loadProgress.Finish();
  stages.emplace_back("load", SecondsSince(start));
  for (const auto & note : loaded.Notes)
  {
    if (chatty)
    {
      std::cerr << "pbdrr: " << note << std::endl;
    }
  }
  loaded.Visit([&](auto * volume) {
    using LoadedType = std::remove_const_t<std::remove_pointer_t<decltype(volume)>>;
    if constexpr (std::is_same_v<LoadedType, TVolume>)
    {
      if (!headerVolume)
      {
        geometry = MakeGeometry(options, volume); // a series' centre, known once it is read
      }
      renderer.Filter->SetInput(volume);
      RenderView(options, loaded, volume, renderer, geometry.GetPointer(), spectrum, stages);
    }
    else
    {
      // A DICOM series of values an int16 does not hold, read as float: the filter of that type, of the same settings.
      const Renderer<LoadedType> floatRenderer = MakeRenderer(options, volume);
      floatRenderer.Filter->SetMemoryBudget(0);
      RenderView(options, loaded, volume, floatRenderer, MakeGeometry(options, volume).GetPointer(), spectrum, stages);
    }
  });
}
} // namespace

void
Run(const Options & options)
{
  if (IsBatch(options))
  {
    RunBatch(options);
    return;
  }
  CheckOptionsApply(options, OptionModes::SingleView);
  const bool                                  chatty = !options.quiet;
  std::vector<std::pair<std::string, double>> stages;
  OutputMode(options); // refuse unknown extensions, and modes they cannot hold, before any work
  if (chatty)
  {
    for (const auto & warning : options.warnings)
    {
      std::cerr << "pbdrr: warning: " << warning << std::endl;
    }
  }
  if (!options.standardErrorOutput.empty())
  {
    if (OutputKind(options.standardErrorOutput) == "png")
    {
      throw UsageError("--stderr needs a float format (.mha, .nrrd, .nii, .tif), not .png");
    }
    if (options.exact)
    {
      throw UsageError("--stderr: an exact render has no statistical error");
    }
    if (options.photons)
    {
      throw UsageError("--stderr is the point estimate's error; with --photons the image has quantum noise on top: "
                       "give one of them");
    }
  }
  struct stat inputStatus;
  if (!options.seriesUID.empty() && stat(options.input.c_str(), &inputStatus) == 0 && !S_ISDIR(inputStatus.st_mode))
  {
    throw UsageError("--series selects a series in a DICOM directory; " + options.input + " is a file");
  }
  CheckWritable(options.output);
  if (!options.standardErrorOutput.empty())
  {
    CheckWritable(options.standardErrorOutput);
  }
  CheckLabelOptions(options);
  const itk::DRRXRaySpectrum::Pointer spectrum = MakeSpectrum(options); // a bad spectrum file stops before the load
  if (options.threads > 0)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.threads);
  }

  const LoadedVolume header = OpenVolumeHeader(options);
  if (header.IsSet())
  {
    header.Visit([&](auto * volume) { LoadAndRenderView(options, header, volume, spectrum, stages); });
  }
  else
  {
    LoadAndRenderView<HUVolumeType>(options, header, nullptr, spectrum, stages);
  }
}

} // namespace pbdrr
