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
#ifndef pbdrrBenchmark_h
#define pbdrrBenchmark_h
// PointBasedDRRBenchmark (see PointBasedDRRBenchmark.cxx): one run of one mode. Its members are defined by what they
// measure: PointBasedDRRBenchmark.cxx (set-up, references, exact projectors, ITK's ray caster, outputs),
// pbdrrBenchmarkTrade.cxx (the speed/accuracy rows of every sampler), pbdrrBenchmarkScaling.cxx,
// pbdrrBenchmarkCollimated.cxx and pbdrrBenchmarkPlastimatch.cxx.
#include "pbdrrBenchmarkOptions.h"
#include "pbdrrBenchmarkTable.h"
#include "pbdrrBenchmarkVolumes.h"

#include "itkExactDRRImageFilter.h"
#include "itkPointBasedDRRImageFilter.h"

#include <functional>
#include <string>
#include <vector>

namespace pbdrr
{
namespace bench
{
using ExactType = itk::ExactDRRImageFilter<VolumeType, ProjectionType>;
using PointFilterType = itk::PointBasedDRRImageFilter<VolumeType, ProjectionType>;
using ImageView = std::function<Image(const Image &)>; // the compared pixels of a rendered image

struct Geometry
{
  unsigned Columns, Rows;
  double   Spacing;
};

/** How the sample ladder of one filter setting is run (LadderRows). */
struct LadderStyle
{
  ImageView View;                 // null: the whole image
  bool      BudgetInNote{ true }; // a skipped row's note names the budget
  bool      CatchErrors{ true };  // a render that throws is a failed row (else the exception goes on)
};

class Benchmark
{
public:
  explicit Benchmark(Options options);

  int
  Run();

private:
  // set up (PointBasedDRRBenchmark.cxx)
  void
  Load();
  itk::DRRProjectionGeometry::Pointer
  MakeGeometry(const VolumeType * volume, unsigned cols, unsigned rows, double spacing) const;
  std::string
  GeometryText(const Geometry & g) const;
  Row
  StartView();
  Timing
  TimeRenders(itk::ProcessObject * filter) const;

  // methods (PointBasedDRRBenchmark.cxx)
  void
  Reference(const VolumeType *           volume,
            itk::DRRProjectionGeometry * geometry,
            KernelEnum                   kernel,
            Image &                      reference,
            Image *                      oneRay,
            MuImageType::Pointer *       mu,
            Row                          base);
  void
  ExactRows(const VolumeType *           volume,
            itk::DRRProjectionGeometry * geometry,
            KernelEnum                   kernel,
            Row                          base,
            const ImageView &            view = nullptr);
  Image
  ItkRayCast(const MuImageType * mu, const itk::DRRProjectionGeometry * geometry, Timing * timing) const;

  // point samplers (pbdrrBenchmarkTrade.cxx)
  Row
  Preprocess(PointFilterType * filter, Row row) const;
  void
  SamplerRows(const std::string & samplerName, const VolumeType * volume, Row base);
  void
  LadderRows(PointFilterType *             filter,
             const std::vector<uint64_t> & ladder,
             const Row &                   base,
             const Image &                 own,
             const LadderStyle &           style);

  // plastimatch (pbdrrBenchmarkPlastimatch.cxx)
  void
  PlastimatchRows(const Row & base);
  void
  PlastimatchRow(const std::string &           algorithm,
                 const itk::Point<double, 3> & iso,
                 const std::string &           muPath,
                 const Row &                   base);

  // modes
  void
  Trade();
  void
  ItkRows(const Row & base, itk::DRRProjectionGeometry * geometry);
  void
  Scaling();
  void
  ScalingSamples(const Row & base);
  void
  ScalingVolume(double fraction, const Row & base, uint64_t samples);
  void
  ScalingDetector(const Row & base, uint64_t samples);
  void
  Collimated();
  void
  CollimatedPoints(const std::string &          samplerName,
                   itk::DRRProjectionGeometry * smallGeometry,
                   itk::DRRProjectionGeometry * fullGeometry,
                   const Row &                  base,
                   const ImageView &            crop);

  // rows and outputs
  void
  Add(Row row, const Image * image = nullptr, const Image * ownReference = nullptr);
  void
  Agreement(const std::string & what, const std::string & against, const Image & a, const Image & b);
  void
  WriteOutputs() const;

  Options                   m_Options;
  VolumeType::Pointer       m_Volume;
  double                    m_LoadSeconds{ NaN };
  std::string               m_VolumeText;
  uint64_t                  m_NonAirVoxels{ 0 };
  MuImageType::Pointer      m_Mu; // identity direction, for ITK and plastimatch
  Image                     m_BoxReference, m_TentReference, m_Siddon1, m_Trilinear1;
  Geometry                  m_Geometry{};
  std::vector<Row>          m_Rows;
  std::vector<AgreementRow> m_Agreement;
  std::string               m_LoadBefore, m_LoadAfter;
  double                    m_Started{ Now() };
};
} // namespace bench
} // namespace pbdrr

#endif
