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
// The speed/accuracy trade of one DRR view of one volume (docs/design.md section 7): every registered sampler with
// every kernel and splat at a ladder of sample counts, the exact projectors, ITK's ray caster and plastimatch, each
// timed (wall, CPU, peak memory) and compared with the exact pixel-averaged reference. Writes OUTDIR/NAME.csv (one
// row per method and setting), OUTDIR/NAME.md (the same as Markdown tables) and OUTDIR/NAME_agreement.csv.
//
//   PointBasedDRRBenchmark INPUT OUTDIR [--mode trade|scaling|collimated] [options]   (--help lists them)
//
// Modes: trade (default) the table above; scaling: time against samples, volume size and detector size;
// collimated: a small detector centred on the view against the same crop of the full render.
// Geometry: plastimatch's drr convention (DRRProjectionGeometry), isocenter at the volume centre, square detector.
//
// The program is split by what it measures: pbdrrBenchmarkOptions (the command line), pbdrrBenchmarkTiming,
// pbdrrBenchmarkTable (rows, CSV and Markdown), pbdrrBenchmarkVolumes, and the members of pbdrr::bench::Benchmark
// (pbdrrBenchmark.h): here the set-up, the exact references and projectors and ITK's ray caster;
// pbdrrBenchmarkTrade.cxx, pbdrrBenchmarkScaling.cxx, pbdrrBenchmarkCollimated.cxx, pbdrrBenchmarkPlastimatch.cxx the
// modes and plastimatch. pbdrrBenchmarkSupport is shared with PointBasedDRRAccuracy and PointBasedDRRPoseRate.
#include "pbdrrBenchmark.h"

#include "itkIdentityTransform.h"
#include "itkMultiThreaderBase.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace pbdrr
{
namespace bench
{
namespace
{
/** An exact projector of the volume with `kernel`, its attenuation volume (HU -> mu) built: `huToMu` seconds. */
ExactType::Pointer
MakeExact(const VolumeType * volume, itk::DRRProjectionGeometry * geometry, KernelEnum kernel, double & huToMu)
{
  auto filter = ExactType::New();
  filter->SetInput(volume);
  filter->SetGeometry(geometry);
  filter->SetReconstructionKernel(kernel);
  const double start = Now();
  filter->GetAttenuationVolume();
  huToMu = Now() - start;
  return filter;
}
} // namespace

Benchmark::Benchmark(Options options) : m_Options(std::move(options))
{}

void
Benchmark::Load()
{
  const double start = Now();
  m_Volume = pbdrr::LoadVolume(m_Options.Input, "").AsFloat();
  m_LoadSeconds = Now() - start;
  const auto         size = m_Volume->GetLargestPossibleRegion().GetSize();
  std::ostringstream text;
  text << size[0] << " x " << size[1] << " x " << size[2] << " voxels of " << Format(m_Volume->GetSpacing()[0], "%.4g")
       << " x " << Format(m_Volume->GetSpacing()[1], "%.4g") << " x " << Format(m_Volume->GetSpacing()[2], "%.4g")
       << " mm";
  const auto & d = m_Volume->GetDirection();
  bool         identity = true;
  for (unsigned r = 0; r < 3; ++r)
    for (unsigned c = 0; c < 3; ++c)
      identity = identity && std::abs(d[r][c] - (r == c ? 1.0 : 0.0)) < 1e-12;
  text << (identity ? ", identity direction" : ", direction not identity");
  m_VolumeText = text.str();
  std::cerr << "volume " << m_Options.Input << ": " << m_VolumeText << ", loaded in " << Format(m_LoadSeconds, "%.3g")
            << " s" << std::endl;
}

itk::DRRProjectionGeometry::Pointer
Benchmark::MakeGeometry(const VolumeType * volume, unsigned cols, unsigned rows, double spacing) const
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetGantryAngleInDegrees(m_Options.Gantry);
  geometry->SetSourceToIsocenterDistance(m_Options.Sad);
  geometry->SetSourceToDetectorDistance(m_Options.Sid);
  geometry->SetIsocenterToImageCenter(volume);
  geometry->SetDetectorSize({ { cols, rows } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(spacing));
  geometry->VerifyGeometry();
  return geometry;
}

std::string
Benchmark::GeometryText(const Geometry & g) const
{
  std::ostringstream text;
  text << g.Columns << " x " << g.Rows << " pixels of " << g.Spacing << " mm, gantry " << m_Options.Gantry
       << " deg, SAD " << m_Options.Sad << " mm, SID " << m_Options.Sid << " mm, isocenter at the volume centre";
  return text.str();
}

/** The view of the options (--cols, --rows, --spacing) as m_Geometry, and a row of this configuration on it. */
Row
Benchmark::StartView()
{
  m_Geometry = { m_Options.Columns, m_Options.Rows, m_Options.Spacing };
  Row base;
  base.Config = m_Options.Name;
  base.Columns = m_Geometry.Columns;
  base.DetectorRows = m_Geometry.Rows;
  return base;
}

/** Median timing of --runs re-renders of a filter (Modified, Update); one if the first is over --repeat-limit. */
Timing
Benchmark::TimeRenders(itk::ProcessObject * filter) const
{
  return Measure(
    [filter] {
      filter->Modified();
      filter->Update();
    },
    m_Options.Runs,
    m_Options.RepeatLimit);
}

/** The exact pixel-averaged reference of one model, timed (one run); optionally its one-ray image and the mu volume
 * the filter integrates. */
void
Benchmark::Reference(const VolumeType *           volume,
                     itk::DRRProjectionGeometry * geometry,
                     KernelEnum                   kernel,
                     Image &                      reference,
                     Image *                      oneRay,
                     MuImageType::Pointer *       mu,
                     Row                          base)
{
  double     huToMu = NaN;
  const auto filter = MakeExact(volume, geometry, kernel, huToMu);
  if (mu)
    *mu = MuImage(volume, filter->GetAttenuationVolume());
  if (volume == m_Volume.GetPointer())
    if (m_NonAirVoxels == 0)
      m_NonAirVoxels = CountNonAir(volume, filter->GetTransferFunction());
  if (oneRay)
  {
    filter->SetRaysPerPixelSide(1);
    filter->Update();
    *oneRay = ToVector(filter->GetOutput());
  }
  filter->SetRaysPerPixelSide(m_Options.ReferenceRays);
  base.Method = "reference";
  base.Kernel = KernelName(kernel);
  base.Model = KernelName(kernel);
  base.Rays = m_Options.ReferenceRays;
  base.HuToMu = huToMu;
  base.Time = Measure([&] { filter->Update(); }, 1, 0.0);
  reference = ToVector(filter->GetOutput());
  base.Note = "exact pixel average (" + std::to_string(base.Rays * base.Rays) + " rays per pixel)";
  Add(base);
}

/** Exact projector rows at the --exact-rays counts; `view` maps the rendered image to the compared pixels. */
void
Benchmark::ExactRows(const VolumeType *           volume,
                     itk::DRRProjectionGeometry * geometry,
                     KernelEnum                   kernel,
                     Row                          base,
                     const ImageView &            view)
{
  const auto filter = MakeExact(volume, geometry, kernel, base.HuToMu);
  filter->SetRaysPerPixelSide(1);
  const double  first = WarmUp(filter.GetPointer());
  const Image & own = kernel == KernelEnum::Box ? m_BoxReference : m_TentReference;
  for (unsigned rays : m_Options.ExactRays)
  {
    Row row = base;
    row.Method = kernel == KernelEnum::Box ? "exact-siddon" : "exact-trilinear";
    row.Kernel = KernelName(kernel);
    row.Model = KernelName(kernel);
    row.Rays = rays;
    row.FirstRender = rays == 1 ? first : NaN;
    filter->SetRaysPerPixelSide(rays);
    row.Time = TimeRenders(filter);
    Image image = ToVector(filter->GetOutput());
    if (view)
      image = view(image);
    Add(row, &image, own.empty() ? nullptr : &own);
  }
}

/** ITK's ray caster as in ITK's Examples/Filtering/DigitallyReconstructedRadiograph1.cxx (MakeRayCaster). The example
 * rotates the volume with a CenteredEuler3DTransform and keeps the camera on the z axis; here the volume stays put
 * (identity transform) and the camera goes where the geometry puts it: the rays run from the source through every
 * pixel centre, as the exact projector's one-ray image. */
Image
Benchmark::ItkRayCast(const MuImageType * mu, const itk::DRRProjectionGeometry * geometry, Timing * timing) const
{
  auto transform = itk::IdentityTransform<double, 3>::New();
  auto resample = MakeRayCaster(mu, geometry, transform);
  if (timing)
    *timing = TimeRenders(resample);
  else
  {
    resample->Modified();
    resample->Update();
  }
  return ToVector(resample->GetOutput());
}

void
Benchmark::Add(Row row, const Image * image, const Image * ownReference)
{
  if (image && ownReference)
    row.Own = Compare(*image, *ownReference);
  if (image && !m_BoxReference.empty() && image->size() == m_BoxReference.size())
    row.Box = Compare(*image, m_BoxReference);
  std::cerr << "  " << std::left << std::setw(11) << row.Sweep << std::setw(20) << row.Method << std::setw(14)
            << row.Sampler << std::setw(5) << row.Kernel << " " << std::setw(9) << row.Splat << std::setw(7)
            << SamplesText(row.Samples)
            << (row.Rays ? std::to_string(row.Rays) + "x" + std::to_string(row.Rays) + " rays " : "") << row.Status
            << "  " << Format(row.Time.Wall, "%.3g") << " s  NRMSE " << Format(row.Own.Nrmse, "%.3g") << std::right
            << std::endl;
  m_Rows.push_back(row);
}

void
Benchmark::Agreement(const std::string & what, const std::string & against, const Image & a, const Image & b)
{
  const Errors e = Compare(a, b);
  m_Agreement.push_back({ what, against, e });
  std::cerr << "  agreement: " << what << " vs " << against << ": NRMSE " << Format(e.Nrmse, "%.3g") << ", sum ratio "
            << Format(e.SumRatio, "%.6f") << std::endl;
}

void
Benchmark::WriteOutputs() const
{
  const std::string prefix = m_Options.OutputDirectory + "/" + m_Options.Name;
  WriteCsv(prefix + ".csv", m_Rows);
  WriteAgreementCsv(prefix + "_agreement.csv", m_Agreement);
  std::ofstream md(prefix + ".md");
  md << "# Benchmark `" << m_Options.Name << "` (" << m_Options.Mode << ")\n\n";
  if (!m_Options.Description.empty())
    md << m_Options.Description << "\n\n";
  md << "- volume: `" << m_Options.Input << "`, " << m_VolumeText << ", " << m_NonAirVoxels
     << " non-air voxels; loaded in " << Format(m_LoadSeconds, "%.3g") << " s\n";
  md << "- view: " << GeometryText({ m_Options.Columns, m_Options.Rows, m_Options.Spacing }) << "\n";
  md << "- machine: " << MachineText() << "; load average (1, 5, 15 min) before " << m_LoadBefore << ", after "
     << m_LoadAfter << "\n";
  md << "- timing: median of " << m_Options.Runs << " runs (one if the first takes over "
     << Format(m_Options.RepeatLimit, "%g") << " s); a setting predicted over " << Format(m_Options.Budget, "%g")
     << " s is skipped; references: " << m_Options.ReferenceRays << " x " << m_Options.ReferenceRays
     << " rays per pixel; seed " << m_Options.Seed << "; total " << Format(Now() - m_Started, "%.0f") << " s\n\n";
  md << "NRMSE and max error are relative to the range (max - min) of the reference of the method's own model (box: "
        "Siddon, tent: trilinear); `vs box` against the box reference. Peak: resident memory of the process (of the "
        "child for plastimatch) during the method; +: over the resident memory before it. See docs/benchmark.md.\n\n";
  WriteMarkdownTables(md, m_Rows, m_Agreement);
}

int
Benchmark::Run()
{
  if (m_Options.Threads)
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(m_Options.Threads);
  std::string mkdir = "mkdir -p '" + m_Options.OutputDirectory + "' '" + m_Options.WorkDirectory + "'";
  if (std::system(mkdir.c_str()) != 0)
    throw std::runtime_error("cannot create " + m_Options.OutputDirectory);
  m_LoadBefore = LoadAverage();
  Load();
  std::cerr << m_Options.Mode << ": " << GeometryText({ m_Options.Columns, m_Options.Rows, m_Options.Spacing })
            << std::endl;
  try
  {
    if (m_Options.Mode == "trade")
      Trade();
    else if (m_Options.Mode == "scaling")
      Scaling();
    else
      Collimated();
  }
  catch (...)
  {
    m_LoadAfter = LoadAverage();
    WriteOutputs(); // what was measured so far
    throw;
  }
  m_LoadAfter = LoadAverage();
  WriteOutputs();
  std::cerr << "wrote " << m_Options.OutputDirectory << "/" << m_Options.Name << ".{csv,md} in "
            << Format(Now() - m_Started, "%.0f") << " s" << std::endl;
  return 0;
}
} // namespace bench
} // namespace pbdrr

int
main(int argc, char * argv[])
{
  try
  {
    pbdrr::bench::Benchmark benchmark(pbdrr::bench::ParseOptions(argc, argv));
    return benchmark.Run();
  }
  catch (const std::exception & e)
  {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
