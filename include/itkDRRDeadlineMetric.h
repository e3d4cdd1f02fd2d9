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
#ifndef itkDRRDeadlineMetric_h
#define itkDRRDeadlineMetric_h

#include "itkObjectToObjectMetricBase.h"

#include <chrono>
#include <limits>

namespace itk
{
/** \class DRRDeadlineMetric
 * \brief The metric as PointBasedDRRRegistrationMethod's optimizers see it. It forwards every call to the metric it
 * watches, and:
 * - presents the parameters in millimetres (with AutomaticParameterScales): parameter j divided by its unit, the RMS
 *   displacement of the kept points per unit of it (the square root of the metric's ComputeParameterScales()), so
 *   that every optimizer, those that take no scales (LBFGSB) included, sees a problem whose units agree;
 * - counts the evaluations and keeps the best pose evaluated;
 * - past the deadline, evaluates nothing: it returns the worst value (1: minus the similarity, which is at least -1)
 *   and a zero derivative, which ends every optimizer's search at once, so that nothing is thrown through an
 *   optimizer's numerical library (LBFGSB's is C).
 *
 * \ingroup PointBasedDRR
 */
class DRRDeadlineMetric : public ObjectToObjectMetricBaseTemplate<double>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRDeadlineMetric);
  using Self = DRRDeadlineMetric;
  using Superclass = ObjectToObjectMetricBaseTemplate<double>;
  using Pointer = SmartPointer<Self>;
  /** Method for creation through the object factory. */
  itkNewMacro(Self);
  using typename Superclass::DerivativeType;
  using typename Superclass::MeasureType;
  using typename Superclass::NumberOfParametersType;
  using typename Superclass::ParametersType;
  using typename Superclass::ParametersValueType;

  /** The metric watched, the units of its parameters (empty: 1) and the deadline. */
  void
  Watch(Superclass * metric, const Array<double> & units, std::chrono::steady_clock::time_point deadline)
  {
    m_Metric = metric;
    m_Units = units;
    if (m_Units.GetSize() != metric->GetNumberOfParameters())
    {
      m_Units.SetSize(metric->GetNumberOfParameters());
      m_Units.Fill(1.0);
    }
    m_Deadline = deadline;
    m_BestValue = std::numeric_limits<double>::infinity();
    m_BestParameters = metric->GetParameters();
    m_Evaluations = 0;
    m_DerivativeEvaluations = 0;
  }

  /** True once an evaluation was asked for past the deadline. */
  bool
  GetTimeIsUp() const
  {
    return m_TimeIsUp;
  }

  /** The lowest value evaluated since Watch() (infinity if none), and its parameters (the metric's own units). */
  double
  GetBestValue() const
  {
    return m_BestValue;
  }
  /** The parameters of GetBestValue(), in the metric's own units. */
  const ParametersType &
  GetBestParameters() const
  {
    return m_BestParameters;
  }

  /** Evaluations since Watch(): all, and those with a derivative. */
  SizeValueType
  GetEvaluations() const
  {
    return m_Evaluations;
  }
  /** Of those, the evaluations with a derivative. */
  SizeValueType
  GetDerivativeEvaluations() const
  {
    return m_DerivativeEvaluations;
  }

  /** Nothing: the method initializes the metric watched, level by level. */
  void
  Initialize() override
  {}

  /** The metric's value (1 past the deadline). */
  MeasureType
  GetValue() const override
  {
    if (this->PastDeadline())
    {
      return this->m_Value = 1.0;
    }
    this->m_Value = m_Metric->GetValue();
    this->Keep(this->m_Value);
    return this->m_Value;
  }

  /** The metric's derivative, per unit of the parameters presented (0 past the deadline). */
  void
  GetDerivative(DerivativeType & derivative) const override
  {
    MeasureType value;
    this->GetValueAndDerivative(value, derivative);
  }

  /** Both, per unit of the parameters presented (1 and 0 past the deadline). */
  void
  GetValueAndDerivative(MeasureType & value, DerivativeType & derivative) const override
  {
    if (this->PastDeadline())
    {
      derivative.SetSize(m_Metric->GetNumberOfParameters());
      derivative.Fill(0.0);
      value = this->m_Value = 1.0;
      return;
    }
    m_Metric->GetValueAndDerivative(value, derivative);
    ++m_DerivativeEvaluations;
    for (unsigned int j = 0; j < derivative.GetSize(); ++j)
    {
      derivative[j] /= m_Units[j]; // d/dq = d/dtheta / unit, q = theta unit
    }
    this->m_Value = value;
    this->Keep(value);
  }

  /** The metric's. */
  NumberOfParametersType
  GetNumberOfParameters() const override
  {
    return m_Metric->GetNumberOfParameters();
  }

  /** The metric's. */
  NumberOfParametersType
  GetNumberOfLocalParameters() const override
  {
    return m_Metric->GetNumberOfLocalParameters();
  }

  /** Sets the metric's parameters from the ones presented (divided by their units). */
  void
  SetParameters(ParametersType & parameters) override
  {
    ParametersType own(parameters.GetSize());
    for (unsigned int j = 0; j < own.GetSize(); ++j)
    {
      own[j] = parameters[j] / m_Units[j];
    }
    m_Metric->SetParameters(own);
  }

  /** The metric's parameters as presented (times their units). */
  const ParametersType &
  GetParameters() const override
  {
    const ParametersType & own = m_Metric->GetParameters();
    m_Scaled.SetSize(own.GetSize());
    for (unsigned int j = 0; j < own.GetSize(); ++j)
    {
      m_Scaled[j] = own[j] * m_Units[j];
    }
    return m_Scaled;
  }

  /** False: one global transform. */
  bool
  HasLocalSupport() const override
  {
    return false;
  }

  /** Updates the metric's transform by an update in the units presented. */
  void
  UpdateTransformParameters(const DerivativeType & update, ParametersValueType factor) override
  {
    DerivativeType own(update.GetSize());
    for (unsigned int j = 0; j < own.GetSize(); ++j)
    {
      own[j] = update[j] / m_Units[j];
    }
    m_Metric->UpdateTransformParameters(own, factor);
  }

protected:
  DRRDeadlineMetric() = default;
  ~DRRDeadlineMetric() override = default;

private:
  bool
  PastDeadline() const
  {
    m_TimeIsUp = m_TimeIsUp || std::chrono::steady_clock::now() > m_Deadline;
    return m_TimeIsUp;
  }

  void
  Keep(double value) const
  {
    ++m_Evaluations;
    if (value < m_BestValue)
    {
      m_BestValue = value;
      m_BestParameters = m_Metric->GetParameters();
    }
  }

  Superclass *                          m_Metric{ nullptr };
  Array<double>                         m_Units;
  std::chrono::steady_clock::time_point m_Deadline{ std::chrono::steady_clock::time_point::max() };
  mutable bool                          m_TimeIsUp{ false };
  mutable double                        m_BestValue{ std::numeric_limits<double>::infinity() };
  mutable ParametersType                m_BestParameters;
  mutable ParametersType                m_Scaled;
  mutable SizeValueType                 m_Evaluations{ 0 };
  mutable SizeValueType                 m_DerivativeEvaluations{ 0 };
};
} // namespace itk

#endif
