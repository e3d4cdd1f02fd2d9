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
#include "itkDRREstimatorChoice.h"
#include "itkDRRExactRayIntegrator.h"
#include "itkDRRPhiloxRandom.h"
#include "itkDRRWorkScheduler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace itk
{
namespace
{
constexpr unsigned int PilotLevels = 4;                // 1, 2, 4 and 8 x 8 rays
constexpr uint64_t     PilotSeed = 0x70696c6f74ULL;    // "pilot": the pilot's pixels are the same in every run
constexpr uint32_t     PilotStream = 7;                // the point renders use streams 0 to 2
constexpr uint64_t     MinimumCandidateSamples = 4096; // fewer points are no render of an image

struct PilotPixel
{
  double Values[PilotLevels]{};
  double Cells{ 0.0 };
  double UnforeseenMisses{ 0.0 };
};

// The reads of a ray the cache has no line for and no prefetcher foresees: the lines of `lines` (the ray's, in order)
// that the previous ray of its tile (the pixel before: `warm`, sorted) did not read, and whose step from the line
// before is not the step before it (a stride prefetcher follows a constant step: an AP ray's rows one after another).
double
CountUnforeseenMisses(const std::vector<uint64_t> & lines, const std::vector<uint64_t> & warm)
{
  double  misses = 0.0;
  int64_t lastStride = 0;
  for (size_t i = 0; i < lines.size(); ++i)
  {
    const int64_t stride = i > 0 ? static_cast<int64_t>(lines[i] - lines[i - 1]) : 0;
    if ((i == 0 || stride != lastStride) && !std::binary_search(warm.begin(), warm.end(), lines[i]))
    {
      misses += 1.0;
    }
    lastStride = stride;
  }
  return misses;
}
} // namespace

constexpr unsigned int DRREstimatorChoice::PilotRaysPerSide[];
constexpr unsigned int DRREstimatorChoice::ExactRaysPerSide[];
constexpr unsigned int DRREstimatorChoice::ControlVariateFactors[];

std::string
DRREstimatorChoice::Candidate::Describe() const
{
  std::ostringstream text;
  if (Kind == Estimator::ExactRays)
  {
    text << "exact " << RaysPerSide << " x " << RaysPerSide << " rays per pixel";
  }
  else
  {
    text << "points " << NumberOfSamples;
    if (ControlVariateFactor > 0)
    {
      text << " with control variate F " << ControlVariateFactor;
    }
  }
  return text.str();
}

void
DRREstimatorChoice::Measure(const DRRAttenuationVolume & volume,
                            KernelEnum                   kernel,
                            const DRRPointProjection &   projection,
                            MultiThreaderBase *          threader)
{
  const DRRExactRayIntegrator integrator(volume, kernel);
  const unsigned int          columns = projection.GetNumberOfColumns();
  const unsigned int          rows = projection.GetNumberOfRows();
  const unsigned int          gridColumns = std::min(PilotGridSide, columns);
  const unsigned int          gridRows = std::min(PilotGridSide, rows);
  std::vector<PilotPixel>     pilot(static_cast<size_t>(gridColumns) * gridRows);
  DRRWorkScheduler::Run(
    threader,
    pilot.size(),
    [&](unsigned int, uint64_t cell) {
      // One pixel drawn in each cell of the grid: the image's content, not a lattice that may beat with it.
      detail::DRRPhiloxRandom                  stream(PilotSeed, cell, PilotStream);
      const detail::DRRPhiloxRandom::BlockType bits = stream.Next();
      const uint64_t                           gc = cell % gridColumns;
      const uint64_t                           gr = cell / gridColumns;
      const uint64_t                           c0 = gc * columns / gridColumns, c1 = (gc + 1) * columns / gridColumns;
      const uint64_t                           r0 = gr * rows / gridRows, r1 = (gr + 1) * rows / gridRows;
      const double column = static_cast<double>(c0 + detail::DRRPhiloxRandom::ToRange(bits[0], bits[1], c1 - c0));
      const double row = static_cast<double>(r0 + detail::DRRPhiloxRandom::ToRange(bits[2], bits[3], r1 - r0));
      PilotPixel & pixel = pilot[cell];
      for (unsigned int level = 0; level < PilotLevels; ++level)
      {
        // The rays of ExactDRRImageFilter's k x k pixel: the centres of a regular subdivision.
        const unsigned int k = PilotRaysPerSide[level];
        double             sum = 0.0;
        for (unsigned int sv = 0; sv < k; ++sv)
        {
          for (unsigned int su = 0; su < k; ++su)
          {
            sum += integrator.IntegrateRay(projection, column + (su + 0.5) / k - 0.5, row + (sv + 0.5) / k - 0.5);
          }
        }
        pixel.Values[level] = sum / (static_cast<double>(k) * k);
      }
      pixel.Cells = integrator.CountCrossedCells(projection, column, row);
      // The rays of a render are traced a tile of a row at a time, column after column (RenderProjection()).
      std::vector<uint64_t> warm = integrator.ListReadCacheLines(projection, column - 1.0, row);
      std::sort(warm.begin(), warm.end());
      pixel.UnforeseenMisses = CountUnforeseenMisses(integrator.ListReadCacheLines(projection, column, row), warm);
    },
    nullptr);

  // Sums in the pilot's order: the same numbers on any threads.
  double       sumOfSquares[PilotLevels - 1]{};
  double       sum = 0.0;
  double       cells = 0.0;
  double       misses = 0.0;
  double       low = std::numeric_limits<double>::infinity();
  double       high = -low;
  const size_t reference = PilotLevels - 1;
  for (const PilotPixel & pixel : pilot)
  {
    for (size_t level = 0; level < reference; ++level)
    {
      const double difference = pixel.Values[level] - pixel.Values[reference];
      sumOfSquares[level] += difference * difference;
    }
    sum += pixel.Values[reference];
    cells += pixel.Cells;
    misses += pixel.UnforeseenMisses;
    low = std::min(low, pixel.Values[reference]);
    high = std::max(high, pixel.Values[reference]);
  }
  const double count = static_cast<double>(pilot.size());
  ViewPilot    view;
  view.Range = high - low;
  if (!(view.Range > 0.0) || !std::isfinite(view.Range))
  {
    itkGenericExceptionMacro("DRREstimatorChoice: the view's pilot of " << pilot.size()
                                                                        << " pixels sees no contrast in the volume "
                                                                           "(every line integral "
                                                                        << high << "): no error to aim at");
  }
  for (size_t level = 0; level < reference; ++level)
  {
    view.ExactRms[level] = std::sqrt(sumOfSquares[level] / count);
  }
  view.MeanLineIntegral = sum / count;
  view.MeanCellsPerRay = cells / count;
  view.MeanUnforeseenMissesPerRay = misses / count;
  m_Views.assign(1, view);
  m_Pixels = static_cast<double>(columns) * rows;
  m_Voxels = static_cast<double>(volume.GetNumberOfVoxels());
}

void
DRREstimatorChoice::AddViews(const DRREstimatorChoice & other)
{
  if (m_Views.empty() || other.m_Views.empty() || other.m_Pixels != m_Pixels || other.m_Voxels != m_Voxels)
  {
    itkGenericExceptionMacro("DRREstimatorChoice: AddViews() needs two measured choices of the same detector ("
                             << m_Pixels << " and " << other.m_Pixels << " pixels) and volume (" << m_Voxels << " and "
                             << other.m_Voxels << " voxels)");
  }
  m_Views.insert(m_Views.end(), other.m_Views.begin(), other.m_Views.end());
}

double
DRREstimatorChoice::GetExactError(unsigned int raysPerSide) const
{
  double largest = 0.0;
  for (const ViewPilot & view : m_Views)
  {
    largest = std::max(largest, view.GetExactError(raysPerSide));
  }
  return largest;
}

double
DRREstimatorChoice::ViewPilot::GetExactError(unsigned int raysPerSide) const
{
  // e_k = RMS(v_k - v_8) / (1 - k / 8): v_8 keeps at most k / 8 of v_k's error (the error falls as 1 / k at least).
  switch (raysPerSide)
  {
    case 1:
      return ExactRms[0] / (1.0 - 1.0 / 8.0) / Range;
    case 2:
      return ExactRms[1] / (1.0 - 2.0 / 8.0) / Range;
    case 4:
      return ExactRms[2] / (1.0 - 4.0 / 8.0) / Range;
    case 8:
      return 0.5 * this->GetExactError(4);
    case 16:
      return 0.25 * this->GetExactError(4);
    default:
      itkGenericExceptionMacro("DRREstimatorChoice: no error model for " << raysPerSide << " rays per pixel side");
  }
}

double
DRREstimatorChoice::GetPointsError(uint64_t samples, unsigned int factor) const
{
  const double controlVariate =
    factor > 0 ? m_Model.ControlVariateErrorScale2 * std::pow(0.5 * factor, m_Model.ControlVariateErrorExponent) : 1.0;
  double largest = 0.0; // mean(L) / range, of the view where it is largest
  for (const ViewPilot & view : m_Views)
  {
    largest = std::max(largest, view.MeanLineIntegral / view.Range);
  }
  return m_Model.PointErrorScale * controlVariate * largest *
         std::sqrt(m_Pixels / static_cast<double>(std::max<uint64_t>(samples, 1)));
}

double
DRREstimatorChoice::GetRayNanoseconds(double cellFraction, bool withMisses) const
{
  // Averaged over the views: their rays are traced in turn, every pose of each.
  double nanoseconds = 0.0;
  for (const ViewPilot & view : m_Views)
  {
    nanoseconds += m_Model.RayNanoseconds + m_Model.CellNanoseconds * cellFraction * view.MeanCellsPerRay +
                   (withMisses ? m_Model.UnforeseenMissNanoseconds * view.MeanUnforeseenMissesPerRay : 0.0);
  }
  return nanoseconds / static_cast<double>(m_Views.size());
}

double
DRREstimatorChoice::GetMeanOverViews(double ViewPilot::*count) const
{
  double sum = 0.0;
  for (const ViewPilot & view : m_Views)
  {
    sum += view.*count;
  }
  return m_Views.empty() ? 0.0 : sum / static_cast<double>(m_Views.size());
}

double
DRREstimatorChoice::ExactSeconds(unsigned int raysPerSide, uint64_t poses) const
{
  const double rays = static_cast<double>(poses) * m_Pixels * raysPerSide * raysPerSide;
  return 1e-9 * rays * this->GetRayNanoseconds(1.0, true);
}

double
DRREstimatorChoice::PointsSeconds(uint64_t samples, unsigned int factor, uint64_t poses) const
{
  const double points = static_cast<double>(samples);
  double       nanoseconds = m_Voxels * m_Model.TableNanosecondsPerVoxel + points * m_Model.PointNanoseconds +
                       static_cast<double>(poses - 1) * points * m_Model.KeptPointNanoseconds;
  if (factor > 0)
  {
    // The coarse volume is F^3 times smaller: it stays in the cache, and its rays cross 1 / F of the cells.
    const double coarseRays = m_Pixels * (m_Model.CoarseRaysPerPixel +
                                          static_cast<double>(poses - 1) * m_Model.CoarseRaysPerPixelAfterTheFirstPose);
    nanoseconds +=
      m_Voxels * m_Model.SplitNanosecondsPerVoxel + coarseRays * this->GetRayNanoseconds(1.0 / factor, false);
  }
  return 1e-9 * nanoseconds;
}

std::vector<DRREstimatorChoice::Candidate>
DRREstimatorChoice::ListCandidates(double target, uint64_t poses, bool controlVariate) const
{
  if (!(target > 0.0) || m_Views.empty())
  {
    itkGenericExceptionMacro("DRREstimatorChoice: ListCandidates() needs a target above 0 and Measure() first");
  }
  poses = std::max<uint64_t>(poses, 1);
  std::vector<Candidate> candidates;
  for (const unsigned int k : ExactRaysPerSide)
  {
    Candidate exact;
    exact.Kind = Estimator::ExactRays;
    exact.RaysPerSide = k;
    exact.Error = this->GetExactError(k);
    exact.Seconds = this->ExactSeconds(k, poses);
    candidates.push_back(exact);
  }
  for (const unsigned int factor : ControlVariateFactors)
  {
    if (factor > 0 && !controlVariate)
    {
      continue;
    }
    // N at which the predicted error is the target: it falls as 1 / sqrt(N).
    const double    ratio = this->GetPointsError(1, factor) / target;
    const double    wanted = std::ceil(ratio * ratio);
    const Candidate points{ Estimator::Points,
                            0,
                            factor,
                            wanted < 1e19 ? std::max<uint64_t>(static_cast<uint64_t>(wanted), MinimumCandidateSamples)
                                          : std::numeric_limits<uint64_t>::max(),
                            0.0,
                            0.0 };
    candidates.push_back(points);
    candidates.back().Error = this->GetPointsError(points.NumberOfSamples, factor);
    candidates.back().Seconds = this->PointsSeconds(points.NumberOfSamples, factor, poses);
  }
  return candidates;
}

DRREstimatorChoice::Candidate
DRREstimatorChoice::Choose(double target, uint64_t poses, bool controlVariate, uint64_t maximumSamples) const
{
  return Choose(this->ListCandidates(target, poses, controlVariate), target, maximumSamples);
}

DRREstimatorChoice::Candidate
DRREstimatorChoice::Choose(const std::vector<Candidate> & candidates, double target, uint64_t maximumSamples)
{
  const Candidate * fastest = FindFastest(candidates, target, maximumSamples, false);
  if (!fastest)
  {
    // The exact candidates are listed first, 16 x 16 rays last of them: the least error any of them reaches.
    const auto finest = std::find_if(candidates.rbegin(), candidates.rend(), [](const Candidate & candidate) {
      return candidate.Kind == Estimator::ExactRays;
    });
    itkGenericExceptionMacro("DRREstimatorChoice: no estimator is predicted to reach the target error "
                             << target << ": " << ExactRaysPerSide[4] << " x " << ExactRaysPerSide[4]
                             << " exact rays per pixel reach " << (finest != candidates.rend() ? finest->Error : 0.0)
                             << ", and points would need more than " << maximumSamples);
  }
  return *fastest;
}

const DRREstimatorChoice::Candidate *
DRREstimatorChoice::FindFastest(const std::vector<Candidate> & candidates,
                                double                         target,
                                uint64_t                       maximumSamples,
                                bool                           exactRaysOnly)
{
  const Candidate * fastest = nullptr;
  for (const Candidate & candidate : candidates)
  {
    const bool exact = candidate.Kind == Estimator::ExactRays;
    const bool allowed = exact || (!exactRaysOnly && candidate.NumberOfSamples <= maximumSamples);
    if (candidate.Error <= target && allowed && (!fastest || candidate.Seconds < fastest->Seconds))
    {
      fastest = &candidate;
    }
  }
  return fastest;
}
} // namespace itk
