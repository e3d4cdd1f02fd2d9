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
// Rigid 2D-3D registration the ITK v4 way: PointBasedDRRMetricv4 (the kept points' DRRs and their analytic pose
// derivative) in an ITK v4 optimizer of your choice, over a VersorRigid3DTransform. The heart is Register(), a dozen
// lines; the rest makes a case whose answer is known.
//
//   Register2D3D [CT] [--optimizer quasinewton|cg|powell] [--views 1|2] [--max-tre MM]
//
// CT: a volume ITK reads (HU); none: a built-in phantom. The X-rays: exact DRRs of the CT where it lies (AP, and
// lateral with --views 2), rendered by ExactDRRImageFilter (2 x 2 rays per pixel). The registration starts 5 mm and 3
// degrees away and prints where it ends; its error is the mean distance (mTRE, mm) between where the found and the
// true pose put the corners of the CT's central half. --max-tre: exit 1 above it.
//
// The optimizers see the transform's own parameters (versor and mm), made commensurate by the metric's scales
// (ComputeParameterScales(): the mean squared motion of the CT's attenuation per unit) and its scales estimator
// (PointBasedDRRParameterScalesEstimator). For a multi-resolution schedule, a time limit, a global stage and the
// optimizers that take no scales (LBFGSB) or normalize their steps in parameter units (RegularStepGradientDescent), use
// itk::PointBasedDRRRegistrationMethod, which composes this metric with any v4 optimizer and presents the parameters
// in millimetres of motion (pbdrr register runs it).
#include "itkConjugateGradientLineSearchOptimizerv4.h"
#include "itkExactDRRImageFilter.h"
#include "itkImageFileReader.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkPointBasedDRRMetricv4.h"
#include "itkPointBasedDRRParameterScalesEstimator.h"
#include "itkPowellOptimizerv4.h"
#include "itkQuasiNewtonOptimizerv4.h"
#include "itkRegularStepGradientDescentOptimizerv4.h"
#include "itkVersorRigid3DTransform.h"

#include <cmath>
#include <iostream>
#include <string>

namespace
{
using CTType = itk::Image<float, 3>;
using MetricType = itk::PointBasedDRRMetricv4<CTType>;
using TransformType = itk::VersorRigid3DTransform<double>;

/** An optimizer of that name for the metric, its steps measured in mm of the CT's motion. */
itk::ObjectToObjectOptimizerBaseTemplate<double>::Pointer
MakeOptimizer(const std::string & name, MetricType * metric)
{
  const MetricType::ScalesType squaredShifts = metric->ComputeParameterScales();
  if (name == "quasinewton" || name == "cg")
  {
    // The gradient-descent family divides the gradient by the scales, the squared displacements per unit, and sizes
    // its steps by the metric's scales estimator: QuasiNewtonOptimizerv4 limits its Newton steps to 3 voxels of
    // motion; the conjugate gradients search each line over up to 5 times the learning rate it estimates (steps of
    // at most a voxel).
    auto estimator = itk::PointBasedDRRParameterScalesEstimator<CTType>::New();
    estimator->SetMetric(metric);
    itk::GradientDescentOptimizerBasev4Template<double>::Pointer optimizer;
    if (name == "cg")
    {
      auto cg = itk::ConjugateGradientLineSearchOptimizerv4::New();
      cg->SetLowerLimit(0.0);
      cg->SetUpperLimit(5.0);
      cg->SetEpsilon(0.01);
      cg->SetDoEstimateLearningRateOnce(true);
      optimizer = cg;
    }
    else
    {
      optimizer = itk::QuasiNewtonOptimizerv4::New();
    }
    optimizer->SetScalesEstimator(estimator);
    optimizer->SetNumberOfIterations(100);
    return optimizer.GetPointer();
  }
  if (name == "powell")
  {
    // Powell divides its steps by the scales: the displacements (mm) per unit.
    auto                                       powell = itk::PowellOptimizerv4<double>::New();
    itk::PowellOptimizerv4<double>::ScalesType shifts(squaredShifts.size());
    for (unsigned int j = 0; j < shifts.size(); ++j)
    {
      shifts[j] = std::sqrt(squaredShifts[j]);
    }
    powell->SetScales(shifts);
    powell->SetStepLength(2.0);
    powell->SetStepTolerance(0.02);
    powell->SetMaximumIteration(8);
    return powell.GetPointer();
  }
  throw std::runtime_error("--optimizer is quasinewton, cg or powell, not " + name);
}

/** The registration: the metric in the optimizer, from the transform's pose. */
void
Register(MetricType * metric, TransformType * transform, const std::string & optimizerName)
{
  metric->SetMovingTransform(transform);
  metric->SetDetectorShrinkFactor(2); // a smoother metric at half resolution; 1 for the last millimetre
  metric->Initialize();
  auto optimizer = MakeOptimizer(optimizerName, metric);
  optimizer->SetMetric(metric);
  optimizer->StartOptimization();
  std::cout << optimizer->GetStopConditionDescription() << "\n"
            << "evaluations: " << metric->GetNumberOfValueEvaluations() << " values, "
            << metric->GetNumberOfDerivativeEvaluations() << " values with the derivative" << std::endl;
}

/** A coarse CT (HU): a soft-tissue ellipsoid with a spine, a rib block and a dense marker, in air: every rotation
 * shows. 48 x 40 x 36 voxels of 5 mm. */
CTType::Pointer
MakePhantom()
{
  auto                ct = CTType::New();
  CTType::SizeType    size{ { 48, 40, 36 } };
  CTType::SpacingType spacing(5.0);
  CTType::PointType   origin;
  for (unsigned a = 0; a < 3; ++a)
    origin[a] = -0.5 * (size[a] - 1) * spacing[a];
  ct->SetRegions(size);
  ct->SetSpacing(spacing);
  ct->SetOrigin(origin);
  ct->Allocate();
  for (itk::ImageRegionIteratorWithIndex<CTType> it(ct, ct->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    CTType::PointType p;
    ct->TransformIndexToPhysicalPoint(it.GetIndex(), p);
    const double x = p[0], y = p[1], z = p[2];
    float        hu = -1000.0f;
    if ((x / 100) * (x / 100) + (y / 80) * (y / 80) < 1.0 && std::abs(z) < 80)
      hu = 20.0f;
    if ((x - 5) * (x - 5) + (y - 45) * (y - 45) < 14 * 14 && std::abs(z) < 75)
      hu = 700.0f;
    if (x > 40 && x < 75 && y > -40 && y < 20 && z > -30 && z < 50)
      hu = 400.0f;
    if ((x + 50) * (x + 50) + (y + 30) * (y + 30) + (z - 40) * (z - 40) < 12 * 12)
      hu = 1500.0f;
    it.Set(hu);
  }
  return ct;
}

/** An exact DRR of the CT where it lies, seen from the gantry angle: 96 x 96 pixels over 1.5 times its extent. */
void
AddXRay(MetricType * metric, const CTType * ct, double gantry)
{
  auto   geometry = itk::DRRProjectionGeometry::New();
  double extent = 0.0;
  for (unsigned a = 0; a < 3; ++a)
    extent = std::max(extent, ct->GetLargestPossibleRegion().GetSize()[a] * ct->GetSpacing()[a]);
  geometry->SetGantryAngleInDegrees(gantry);
  geometry->SetIsocenterToImageCenter(ct);
  geometry->SetDetectorSize({ { 96, 96 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(1.5 * 1.5 * extent / 96)); // SID / SAD = 1.5
  auto exact = itk::ExactDRRImageFilter<CTType, MetricType::XRayImageType>::New();
  exact->SetInput(ct);
  exact->SetGeometry(geometry);
  exact->SetRaysPerPixelSide(2);
  exact->Update();
  metric->AddXRay(exact->GetOutput(), geometry);
}

/** Mean distance (mm) between where the transform and the identity put the 8 corners of the CT's central half. */
double
MeanTargetError(const CTType * ct, const TransformType * transform)
{
  const auto size = ct->GetLargestPossibleRegion().GetSize();
  double     sum = 0.0;
  for (unsigned corner = 0; corner < 8; ++corner)
  {
    itk::ContinuousIndex<double, 3> index;
    for (unsigned a = 0; a < 3; ++a)
      index[a] = (size[a] - 1) * ((corner >> a) & 1u ? 0.75 : 0.25);
    CTType::PointType point;
    ct->TransformContinuousIndexToPhysicalPoint(index, point);
    sum += (transform->TransformPoint(point) - point).GetNorm();
  }
  return sum / 8.0;
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    std::string input, optimizer = "quasinewton";
    unsigned    views = 2;
    double      maxTre = -1.0;
    for (int a = 1; a < argc; ++a)
    {
      const std::string arg = argv[a];
      if (arg == "--optimizer" && a + 1 < argc)
        optimizer = argv[++a];
      else if (arg == "--views" && a + 1 < argc)
        views = static_cast<unsigned>(std::stoul(argv[++a]));
      else if (arg == "--max-tre" && a + 1 < argc)
        maxTre = std::stod(argv[++a]);
      else if (!arg.empty() && arg[0] != '-')
        input = arg;
      else
        throw std::runtime_error("usage: Register2D3D [CT] [--optimizer quasinewton|cg|powell] [--views 1|2] "
                                 "[--max-tre MM]");
    }
    const CTType::Pointer ct = input.empty() ? MakePhantom() : itk::ReadImage<CTType>(input);
    auto                  metric = MetricType::New();
    metric->SetVolume(ct);
    AddXRay(metric, ct, 90.0); // AP
    if (views > 1)
      AddXRay(metric, ct, 0.0); // lateral
    metric->SetNumberOfSamples(500000);

    // The moving transform maps the room to the CT (as the DRR filters and ITK's ray caster take it), about its
    // centre; the start: 5 mm and 3 degrees off.
    auto transform = TransformType::New();
    transform->SetCenter(itk::DRRProjectionGeometry::ComputeImageCenter(ct));
    itk::Vector<double, 3> axis;
    axis[0] = 0.6;
    axis[1] = -0.48;
    axis[2] = 0.64;
    transform->SetRotation(axis, 3.0 * 3.14159265358979323846 / 180.0);
    transform->SetTranslation(itk::Vector<double, 3>(5.0 / std::sqrt(3.0)));
    const double start = MeanTargetError(ct, transform);

    Register(metric, transform, optimizer);

    const double tre = MeanTargetError(ct, transform);
    std::cout << "mTRE: " << start << " mm at the start, " << tre << " mm at the end" << std::endl;
    return maxTre >= 0.0 && !(tre <= maxTre) ? 1 : 0;
  }
  catch (const std::exception & error)
  {
    std::cerr << "Register2D3D: " << error.what() << std::endl;
    return 1;
  }
}
