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
#ifndef itkPointBasedDRRParameterScalesEstimator_h
#define itkPointBasedDRRParameterScalesEstimator_h

#include "itkOptimizerParameterScalesEstimator.h"
#include "itkPointBasedDRRMetricv4.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace itk
{
/** \class PointBasedDRRParameterScalesEstimator
 * \brief The parameter scales of a PointBasedDRRMetricv4 for ITK's v4 optimizers (SetScalesEstimator()), from the
 * motion of the CT's attenuation in the room, as RegistrationParameterScalesFromJacobian does for an image metric.
 *
 * ITK's v4 scales estimators read an image metric's virtual domain, which a 2D-3D metric has not: this one reads the
 * metric's own sample, a few thousand of its kept points (PointBasedDRRMetricv4::ComputeParameterScales(),
 * ComputeMaximumDisplacement()):
 * - EstimateScales(): per parameter, the mean squared displacement (mm^2) of the points per unit of it;
 * - EstimateStepScale(): the largest displacement (mm) of the points for a step of the parameters;
 * - EstimateMaximumStepSize(): the CT's smallest voxel spacing (mm), as ITK's estimators take the virtual domain's.
 * With it, GradientDescentOptimizerv4's learning-rate estimation and QuasiNewtonOptimizerv4 (which needs an
 * estimator) work on the metric. The transform has no local support: EstimateLocalStepScales() throws.
 *
 * The metric must have been initialized (Initialize()) before the optimizer starts.
 *
 * \sa PointBasedDRRMetricv4, OptimizerParameterScalesEstimatorTemplate
 * \ingroup PointBasedDRR
 */
template <typename TVolumeImage>
class ITK_TEMPLATE_EXPORT PointBasedDRRParameterScalesEstimator
  : public OptimizerParameterScalesEstimatorTemplate<double>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(PointBasedDRRParameterScalesEstimator);

  /** Standard class type aliases. */
  using Self = PointBasedDRRParameterScalesEstimator;
  using Superclass = OptimizerParameterScalesEstimatorTemplate<double>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  /** The metric whose parameters are scaled. */
  using MetricType = PointBasedDRRMetricv4<TVolumeImage>;
  using typename Superclass::FloatType;
  using typename Superclass::ParametersType;
  using typename Superclass::ScalesType;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(PointBasedDRRParameterScalesEstimator);

  ///@{
  /** The metric (not owned by an optimizer: set the same one as the optimizer's). */
  itkSetObjectMacro(Metric, MetricType);
  itkGetModifiableObjectMacro(Metric, MetricType);
  ///@}

  /** Per parameter, the mean squared displacement (mm^2) of the metric's sample points per unit of it. */
  void
  EstimateScales(ScalesType & scales) override
  {
    scales = this->VerifiedMetric()->ComputeParameterScales();
  }

  /** The largest displacement (mm) of the metric's sample points for step. */
  FloatType
  EstimateStepScale(const ParametersType & step) override
  {
    return this->VerifiedMetric()->ComputeMaximumDisplacement(step);
  }

  /** Throws: the metric's transform has no local support. */
  void
  EstimateLocalStepScales(const ParametersType &, ScalesType &) override
  {
    itkExceptionMacro("the metric's transform has no local support: no local step scales");
  }

  /** The CT's smallest voxel spacing, mm: the largest step a v4 optimizer should take by default. */
  FloatType
  EstimateMaximumStepSize() override
  {
    const auto * model = this->VerifiedMetric()->GetAttenuationModel();
    if (!model)
    {
      itkExceptionMacro("the metric has no model yet: call its Initialize() first");
    }
    const auto matrix = model->GetIndexToPhysicalMatrix();
    double     smallest = std::numeric_limits<double>::infinity();
    for (unsigned int c = 0; c < 3; ++c)
    {
      smallest = std::min(
        smallest, std::sqrt(matrix[0][c] * matrix[0][c] + matrix[1][c] * matrix[1][c] + matrix[2][c] * matrix[2][c]));
    }
    return smallest;
  }

protected:
  PointBasedDRRParameterScalesEstimator() = default;
  ~PointBasedDRRParameterScalesEstimator() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override
  {
    Superclass::PrintSelf(os, indent);
    os << indent << "Metric: " << m_Metric.GetPointer() << std::endl;
  }

private:
  MetricType *
  VerifiedMetric()
  {
    if (!m_Metric)
    {
      itkExceptionMacro("no metric (SetMetric())");
    }
    return m_Metric;
  }

  typename MetricType::Pointer m_Metric;
};
} // namespace itk

#endif
