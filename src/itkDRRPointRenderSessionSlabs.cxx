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
// The session's streamed render (docs/design.md section 16): two passes over the slabs, the view's masses and the
// coarse volume first, then every slab's window of the run's samples.
#include "itkDRRPointRenderSession.h"
#include "itkDRRControlVariate.h"
#include "itkDRRStratifiedSampler.h"
#include "itkDRRStreamedPointRender.h"

#include <vector>

namespace itk
{
/** One streamed render: the slab held (its model, split and sampler's tables), and what the first pass measured. */
class DRRPointRenderSession::StreamedRender
{
public:
  using Placement = DRRStratifiedSampler::SlabPlacement;

  StreamedRender(const Request &                    request,
                 const DRRPointRenderer::Settings & settings,
                 const Slabs &                      slabs,
                 const DRRPointProjection &         projection,
                 MultiThreaderBase *                threader,
                 ProcessObject *                    caller,
                 bool                               keepPoints)
    : m_Request(request)
    , m_Settings(settings)
    , m_Slabs(slabs)
    , m_Projection(projection)
    , m_Threader(threader)
    , m_Caller(caller)
    , m_KeepPoints(keepPoints)
    , m_MassBefore(slabs.NumberOfSlabs, 0.0)
  {}

  /** First pass: the view's mass along the curve before each slab, the whole volume's mass and the coarse volume, and
   * the channels of the slabs' models; for `auto`, the pass again without a control variate if the split is declined.
   */
  void
  MeasureSlabs(unsigned int factor)
  {
    m_Factor = factor;
    while (!this->MeasureSlabsOnce())
    {
      m_Factor = 0; // `auto` declines as the unstreamed render does (Prepare())
    }
    m_Settings.NumberOfChannels = m_NumberOfChannels;
  }

  /** Second pass: every slab draws its window of the run's samples into the whole render's sums, or into kept points
   * (returned; the result is then empty). */
  DRRPointRenderer::Result
  DrawSlabs(DRRPointCloud::Pointer & cloud)
  {
    const DRRSamplerTraits                  traits = m_Sampler->GetTraits();
    const DRRPointSampler::SampleRange      run = DRRStreamedPointRender::MakeRun(m_Settings, traits);
    const std::array<uint64_t, 3> &         wholeSize = m_Slabs.WholeSize;
    const double                            voxelVolume = m_Slabs.Grid->GetVoxelVolume();
    std::unique_ptr<DRRStreamedPointRender> render;
    if (m_KeepPoints)
    {
      cloud = DRRStreamedPointRender::MakeCloud(
        m_Settings, traits, m_Sampler->GetMaximumWeight(), wholeSize, m_ViewMass * voxelVolume, m_Factor != 0);
    }
    else
    {
      render = std::make_unique<DRRStreamedPointRender>(
        m_Settings, m_Projection, traits, m_Sampler->GetMaximumWeight(), wholeSize, m_Threader);
    }
    const unsigned int slabs = m_Slabs.NumberOfSlabs;
    for (unsigned int slab = 0; slab < slabs; ++slab)
    {
      this->CheckAbort();
      if (slab <= m_LastSlabInView && m_ViewVoxels > 0)
      {
        this->DrawSlab(slab, run, cloud.GetPointer(), render.get());
      }
      this->Progress(0.5f + 0.5f * static_cast<float>(slab + 1) / static_cast<float>(slabs));
    }
    this->DropSlab();
    if (m_ControlVariate)
    {
      m_ControlVariate->EndSlabs(m_Threader);
    }
    if (m_KeepPoints)
    {
      return {};
    }
    return render->Finish(m_SampledTotal * voxelVolume, m_ViewMass * voxelVolume);
  }

  /** The coarse volume of the whole (null: no control variate). */
  DRRControlVariate::Pointer
  GetControlVariate() const
  {
    return m_ControlVariate;
  }

private:
  bool
  MeasureSlabsOnce()
  {
    m_ViewMass = 0.0;
    m_ViewVoxels = 0;
    m_SampledTotal = 0.0;
    m_NumberOfChannels = 0;
    m_ControlVariate = nullptr;
    if (m_Factor != 0)
    {
      const std::array<uint64_t, 3> & size = m_Slabs.WholeSize;
      m_ControlVariate = DRRControlVariate::New();
      m_ControlVariate->BeginSlabs({ { size[0], size[1], size[2] } },
                                   m_Slabs.Grid->GetIndexToPhysicalMatrix(),
                                   m_Slabs.Grid->GetOrigin(),
                                   m_Factor);
    }
    const unsigned int slabs = m_Slabs.NumberOfSlabs;
    for (unsigned int slab = 0; slab < slabs; ++slab)
    {
      this->CheckAbort();
      this->ReadSlab(slab);
      if (!this->CountChannels(slab))
      {
        return false; // channels: `auto` declines its split, as the unstreamed render does (ResolveFactor())
      }
      Placement placement;
      placement.FirstPlane = m_Slabs.FirstPlane(slab);
      placement.MassBefore = m_ViewMass;
      m_MassBefore[slab] = m_ViewMass;
      const auto plan = this->MakePlan(placement);
      m_ViewMass = DRRStratifiedSampler::GetMassAtEnd(*plan);
      const uint64_t voxels = DRRStratifiedSampler::GetNumberOfVoxelsInPlan(*plan);
      m_ViewVoxels += voxels;
      m_LastSlabInView = voxels > 0 ? slab : m_LastSlabInView;
      placement.MassBefore = m_SampledTotal;
      m_SampledTotal = DRRStratifiedSampler::GetMassAtEnd(*m_Sampler->MakeSlabViewPlan(nullptr, 0.0, 0.0, placement));
      if (m_ControlVariate)
      {
        m_ControlVariate->AddSlab(*m_SlabControlVariate, placement.FirstPlane);
      }
      this->Progress(0.5f * static_cast<float>(slab + 1) / static_cast<float>(slabs));
    }
    const bool declined = m_ControlVariate && m_Request.ControlVariateFactor == DRRControlVariate::AutomaticFactor &&
                          m_SampledTotal * m_Slabs.Grid->GetVoxelVolume() >
                            MaximumAutomaticResidualFraction * m_ControlVariate->GetTotalMass();
    return !declined;
  }

  /** The slabs' channels are the whole volume's: every slab's model numbers them alike (the labels of the whole label
   * image, the materials of the table), which a slab's own labels would not. False if they decline the split: the
   * number of channels is known from the first slab read, after F was chosen. */
  bool
  CountChannels(unsigned int slab)
  {
    const unsigned int channels = m_SlabVolume->GetNumberOfChannels();
    if (m_NumberOfChannels != 0 && channels != m_NumberOfChannels)
    {
      itkGenericExceptionMacro("the model of slab " << slab << " has " << channels << " channels, the first slab's "
                                                    << m_NumberOfChannels
                                                    << ": the slabs' channels must be numbered as the whole volume's");
    }
    m_NumberOfChannels = channels;
    if (channels > 1 && m_Factor != 0)
    {
      RefuseChosenFactorForChannels(m_Request);
      return false;
    }
    return true;
  }

  void
  DrawSlab(unsigned int                         slab,
           const DRRPointSampler::SampleRange & run,
           DRRPointCloud *                      cloud,
           DRRStreamedPointRender *             render)
  {
    Placement placement;
    placement.FirstPlane = m_Slabs.FirstPlane(slab);
    placement.MassBefore = m_MassBefore[slab];
    placement.ViewMass = m_ViewMass;
    placement.ViewVoxels = m_ViewVoxels;
    placement.LastSlab = slab == m_LastSlabInView;
    this->ReadSlab(slab);
    const auto                   plan = this->MakePlan(placement);
    const auto                   window = DRRStratifiedSampler::GetSampleWindow(*plan, run);
    const DRRAttenuationVolume * residual = m_SlabControlVariate ? &m_SlabControlVariate->GetResidualVolume() : nullptr;
    if (cloud)
    {
      DRRPointRenderer::Settings slabSettings = m_Settings;
      slabSettings.SignedResidual = residual;
      slabSettings.VoxelChannels = m_SlabVolume->GetVoxelChannels();
      DRRStreamedPointRender::DrawSlab(
        *cloud, slabSettings, *plan, *m_Sampler, window, placement.FirstPlane, m_Threader, nullptr);
    }
    else
    {
      render->AddSlab(*plan, *m_Sampler, window, placement.FirstPlane, residual, m_SlabVolume->GetVoxelChannels());
    }
  }

  /** A slab's model, its control variate (its own residual; its coarse planes are the whole one's) and the tables of
   * a sampler of the slab's own (the session's sampler keeps its tables of the whole volume, if any). */
  void
  ReadSlab(unsigned int slab)
  {
    // The last slab's tables and model go before this one is read: they hold its voxels (the model reads them in
    // place), which would otherwise stay beside the new ones.
    this->DropSlab();
    m_SlabVolume = m_Slabs.Read(slab);
    m_Sampler = DRRStratifiedSampler::New();
    if (m_Factor != 0)
    {
      m_SlabControlVariate = DRRControlVariate::New();
      m_Sampler->InitializeWithControlVariate(*m_SlabControlVariate, *m_SlabVolume, m_Factor, m_Threader);
    }
    else
    {
      m_Sampler->Initialize(*m_SlabVolume);
    }
  }

  void
  DropSlab()
  {
    m_Sampler = nullptr;
    m_SlabControlVariate = nullptr;
    m_SlabVolume = nullptr;
  }

  /** Kept points serve every view: the whole volume's plan, not culled. */
  DRRPointSampler::ViewPlanConstPointer
  MakePlan(const Placement & placement) const
  {
    return m_KeepPoints ? m_Sampler->MakeSlabViewPlan(nullptr, 0.0, 0.0, placement)
                        : DRRStreamedPointRender::MakeSlabPlan(*m_Sampler, m_Projection, m_Settings, placement);
  }

  void
  CheckAbort() const
  {
    if (m_Caller && m_Caller->GetAbortGenerateData())
    {
      ProcessAborted aborted(__FILE__, __LINE__);
      aborted.SetDescription("the streamed render was aborted between slabs");
      throw aborted;
    }
  }

  void
  Progress(float progress) const
  {
    if (m_Caller)
    {
      m_Caller->UpdateProgress(progress);
    }
  }

  const Request &            m_Request;
  DRRPointRenderer::Settings m_Settings; // with the slabs' number of channels once measured
  const Slabs &              m_Slabs;
  const DRRPointProjection & m_Projection;
  MultiThreaderBase *        m_Threader;
  ProcessObject *            m_Caller;
  const bool                 m_KeepPoints;

  unsigned int                  m_Factor{ 0 };
  DRRAttenuationVolume::Pointer m_SlabVolume;
  DRRControlVariate::Pointer    m_SlabControlVariate;
  DRRStratifiedSampler::Pointer m_Sampler;

  std::vector<double>        m_MassBefore; // the view's mass along the curve before each slab, 1/mm
  double                     m_ViewMass{ 0.0 };
  uint64_t                   m_ViewVoxels{ 0 };
  double                     m_SampledTotal{ 0.0 };   // the mass the sampler draws from (the residual's with F), 1/mm
  unsigned int               m_NumberOfChannels{ 0 }; // of every slab's model
  unsigned int               m_LastSlabInView{ 0 };
  DRRControlVariate::Pointer m_ControlVariate;
};

DRRPointRenderer::Result
DRRPointRenderSession::Render(const Request &            request,
                              uint64_t                   samples,
                              const Slabs &              slabs,
                              const DRRPointProjection & projection,
                              MultiThreaderBase *        threader,
                              ProcessObject *            caller)
{
  if (!request.Sampler || !WhyNotStreamable(*request.Sampler).empty())
  {
    itkGenericExceptionMacro("streaming needs the stratified sampler");
  }
  const unsigned int               pass = m_Passes.GetNumberOfPasses();
  const bool                       keepPoints = request.ReusePoints && pass == 0;
  const DRRPointRenderer::Settings settings = MakePassSettings(request, samples, pass, nullptr);
  if (keepPoints && !this->StreamedPointsAreCurrent(request, slabs.MadeOf))
  {
    m_PointCloud = nullptr; // free the old points before drawing new ones
    m_StreamedControlVariate = nullptr;
    StreamedRender draw(request, settings, slabs, projection, threader, caller, true);
    draw.MeasureSlabs(ResolveStreamedFactor(request, *slabs.Grid, slabs.WholeSize, projection));
    draw.DrawSlabs(m_PointCloud);
    m_PointCloudStreamed = true;
    m_PointCloudDrawnWith = MakeDrawnWith(request, samples);
    m_StreamedControlVariate = draw.GetControlVariate();
    m_PointCloudTime.Modified();
    ++m_NumberOfPointCloudDraws;
  }
  DRRPointRenderer::Result   result;
  DRRControlVariate::Pointer controlVariate = m_StreamedControlVariate;
  if (keepPoints)
  {
    result = this->RenderKeptPoints(settings, projection, threader, caller);
  }
  else
  {
    StreamedRender render(request, settings, slabs, projection, threader, caller, false);
    render.MeasureSlabs(ResolveStreamedFactor(request, *slabs.Grid, slabs.WholeSize, projection));
    DRRPointCloud::Pointer none;
    result = render.DrawSlabs(none);
    controlVariate = render.GetControlVariate();
  }
  if (controlVariate)
  {
    this->AddCoarseImage(*controlVariate, request, settings, projection, threader, caller, result);
  }
  return result;
}
} // namespace itk
