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
// What a derivative costs (issue 38): PointBasedDRRMetricv4's GetValue() against GetValueAndDerivative(), side by
// side in one run, the median of 15 of each, per number of kept points and detector shrink factor.
//
//   PointBasedDRRMetricCost CT XRAY GEOMETRY [--threads N]
//
// CT: a DICOM series directory or a volume file; XRAY and GEOMETRY: an X-ray and its view (pbdrr register's --xray and
// --geometry; benchmark/registration.sh writes out/registration/chest-ap/ap.mha and ap.geometry.txt). One line per
// setting: points, shrink, value ms, value and derivative ms, their ratio.
#include "pbdrrBenchmarkSupport.h"
#include "pbdrrRegistration.h"
#include "pbdrrVolumeLoader.h"

#include "itkPointBasedDRRMetricv4.h"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <vector>

namespace
{
using MetricType = itk::PointBasedDRRMetricv4<pbdrr::VolumeType>;

double
Median(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}
} // namespace

int
main(int argc, char * argv[])
{
  if (argc != 4 && !(argc == 6 && std::string(argv[4]) == "--threads"))
  {
    std::cerr << "usage: " << argv[0] << " CT XRAY GEOMETRY [--threads N]" << std::endl;
    return 2;
  }
  try
  {
    const unsigned                   threads = argc == 6 ? static_cast<unsigned>(std::stoul(argv[5])) : 2;
    const pbdrr::VolumeType::Pointer ct = pbdrr::LoadVolume(argv[1], "").AsFloat();
    const pbdrr::XRay                xray = pbdrr::ReadXRay(argv[2], argv[3], "", ct);
    std::printf("points shrink value_ms value_and_derivative_ms ratio (median of 15, %u threads)\n", threads);
    for (const double points : { 1e6, 4e6 })
    {
      for (const unsigned shrink : { 1u, 2u, 4u })
      {
        auto metric = MetricType::New();
        metric->SetVolume(ct);
        metric->AddXRay(xray.Image, xray.Geometry);
        metric->SetNumberOfSamples(static_cast<uint64_t>(points));
        metric->SetDetectorShrinkFactor(shrink);
        metric->SetNumberOfWorkUnits(threads);
        metric->Initialize();
        std::vector<double>        value, both;
        MetricType::DerivativeType derivative;
        double                     measure = 0.0;
        for (int k = 0; k < 15; ++k)
        {
          const double start = pbdrr::bench::Now();
          measure = metric->GetValue();
          const double middle = pbdrr::bench::Now();
          metric->GetValueAndDerivative(measure, derivative);
          value.push_back(middle - start);
          both.push_back(pbdrr::bench::Now() - middle);
        }
        std::printf("%.0e %u %.2f %.2f %.2f\n",
                    points,
                    shrink,
                    1e3 * Median(value),
                    1e3 * Median(both),
                    Median(both) / Median(value));
      }
    }
  }
  catch (const std::exception & error)
  {
    std::cerr << argv[0] << ": " << error.what() << std::endl;
    return 1;
  }
  return 0;
}
