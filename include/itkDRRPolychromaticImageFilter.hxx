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
#ifndef itkDRRPolychromaticImageFilter_hxx
#define itkDRRPolychromaticImageFilter_hxx

#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIterator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace itk
{
template <typename TChannelImage, typename TOutputImage>
DRRPolychromaticImageFilter<TChannelImage, TOutputImage>::DRRPolychromaticImageFilter()
{
  this->SetNumberOfRequiredOutputs(2);
  this->SetNthOutput(1, this->MakeOutput(1));
  this->DynamicMultiThreadingOn();
}

template <typename TChannelImage, typename TOutputImage>
void
DRRPolychromaticImageFilter<TChannelImage, TOutputImage>::BeforeThreadedGenerateData()
{
  if (!m_MaterialTable)
  {
    itkExceptionMacro("no material table (SetMaterialTable()): it says which material each channel is");
  }
  if (!m_Spectrum || m_Spectrum->GetNumberOfBins() == 0)
  {
    itkExceptionMacro("no X-ray spectrum (SetSpectrum() with a DRRXRaySpectrum that has bins)");
  }
  if (!(m_ReferenceEnergyInKeV >= DRRMaterialTable::MinimumEnergyInKeV &&
        m_ReferenceEnergyInKeV <= DRRMaterialTable::MaximumEnergyInKeV))
  {
    itkExceptionMacro("the reference energy must be in [" << DRRMaterialTable::MinimumEnergyInKeV << ", "
                                                          << DRRMaterialTable::MaximumEnergyInKeV << "] keV, got "
                                                          << m_ReferenceEnergyInKeV);
  }
  const ChannelImageType * input = this->GetInput();
  const unsigned int       K = input->GetNumberOfComponentsPerPixel();
  if (K != m_MaterialTable->GetNumberOfMaterials())
  {
    itkExceptionMacro("the channel image has " << K << " channels, the material table "
                                               << m_MaterialTable->GetNumberOfMaterials()
                                               << " materials: channel m must be material m");
  }
  const OutputImageRegionType region = this->GetOutput()->GetRequestedRegion();
  for (ImageRegionConstIteratorWithIndex<ChannelImageType> it(input, region); !it.IsAtEnd(); ++it)
  {
    const auto pixel = it.Get();
    for (unsigned int m = 0; m < K; ++m)
    {
      if (!std::isfinite(static_cast<double>(pixel[m])))
      {
        itkExceptionMacro("channel " << m << " of pixel " << it.GetIndex() << " is " << pixel[m]
                                     << ": line integrals must be finite");
      }
    }
  }
  const ChannelImageType * covariance = this->GetCovarianceInput();
  if (covariance)
  {
    if (covariance->GetNumberOfComponentsPerPixel() != K * (K + 1) / 2)
    {
      itkExceptionMacro("the covariance image has " << covariance->GetNumberOfComponentsPerPixel() << " components; "
                                                    << K << " channels need K(K+1)/2 = " << K * (K + 1) / 2);
    }
    if (covariance->GetLargestPossibleRegion() != input->GetLargestPossibleRegion())
    {
      itkExceptionMacro("the covariance image's region " << covariance->GetLargestPossibleRegion()
                                                         << " is not the channel image's "
                                                         << input->GetLargestPossibleRegion());
    }
    for (ImageRegionConstIteratorWithIndex<ChannelImageType> it(covariance, region); !it.IsAtEnd(); ++it)
    {
      const auto   pixel = it.Get();
      unsigned int c = 0;
      for (unsigned int m = 0; m < K; ++m)
      {
        for (unsigned int n = m; n < K; ++n, ++c)
        {
          const double value = static_cast<double>(pixel[c]);
          if (!std::isfinite(value) || (n == m && value < 0.0))
          {
            itkExceptionMacro("covariance ("
                              << m << ", " << n << ") of pixel " << it.GetIndex() << " is " << value
                              << (n == m ? ": a variance must be finite and >= 0" : ": a covariance must be finite"));
          }
        }
      }
    }
  }

  // k_m(E) and the weights S(E) / sum S, over the bins of nonzero fluence.
  const std::vector<double> & energies = m_Spectrum->GetEnergies();
  const std::vector<double> & fluence = m_Spectrum->GetFluence();
  double                      total = 0.0;
  std::vector<size_t>         bins;
  for (size_t e = 0; e < energies.size(); ++e)
  {
    if (fluence[e] > 0.0)
    {
      bins.push_back(e);
      total += fluence[e];
    }
  }
  m_Weights.resize(bins.size());
  m_Ratios.resize(K * bins.size());
  for (size_t b = 0; b < bins.size(); ++b)
  {
    m_Weights[b] = fluence[bins[b]] / total;
  }
  for (unsigned int m = 0; m < K; ++m)
  {
    const double reference = m_MaterialTable->GetMassAttenuation(m, m_ReferenceEnergyInKeV);
    for (size_t b = 0; b < bins.size(); ++b)
    {
      m_Ratios[m * bins.size() + b] = m_MaterialTable->GetMassAttenuation(m, energies[bins[b]]) / reference;
    }
  }
}

template <typename TChannelImage, typename TOutputImage>
void
DRRPolychromaticImageFilter<TChannelImage, TOutputImage>::DynamicThreadedGenerateData(
  const OutputImageRegionType & region)
{
  using OutputPixelType = typename OutputImageType::PixelType;
  const ChannelImageType * input = this->GetInput();
  const ChannelImageType * covariance = this->GetCovarianceInput();
  const unsigned int       K = input->GetNumberOfComponentsPerPixel();
  const size_t             nE = m_Weights.size();
  const bool               jensen = m_CorrectJensenBias && covariance != nullptr;

  std::vector<double>                                 L(K), C(K * K, 0.0), exponent(nE), scaled(nE), h(K);
  ImageRegionIterator<OutputImageType>                out(this->GetOutput(), region);
  ImageRegionIterator<OutputImageType>                error(this->GetOutput(1), region);
  ImageRegionConstIteratorWithIndex<ChannelImageType> cov;
  if (covariance)
  {
    cov = ImageRegionConstIteratorWithIndex<ChannelImageType>(covariance, region);
  }
  for (ImageRegionConstIteratorWithIndex<ChannelImageType> in(input, region); !in.IsAtEnd(); ++in, ++out, ++error)
  {
    const auto pixel = in.Get();
    for (unsigned int m = 0; m < K; ++m)
    {
      L[m] = static_cast<double>(pixel[m]);
    }
    if (covariance)
    {
      const auto   c = cov.Get();
      unsigned int i = 0;
      for (unsigned int m = 0; m < K; ++m)
      {
        for (unsigned int n = m; n < K; ++n, ++i)
        {
          C[m * K + n] = C[n * K + m] = static_cast<double>(c[i]);
        }
      }
      ++cov;
    }
    // x_E = k(E).L (+ k^T C k / 2); -ln T = x_min - ln sum_E w_E exp(-(x_E - x_min)): finite for any finite input.
    double smallest = std::numeric_limits<double>::infinity();
    for (size_t e = 0; e < nE; ++e)
    {
      double x = 0.0;
      for (unsigned int m = 0; m < K; ++m)
      {
        x += m_Ratios[m * nE + e] * L[m];
      }
      if (jensen)
      {
        double q = 0.0;
        for (unsigned int m = 0; m < K; ++m)
        {
          for (unsigned int n = 0; n < K; ++n)
          {
            q += m_Ratios[m * nE + e] * C[m * K + n] * m_Ratios[n * nE + e];
          }
        }
        x += 0.5 * q;
      }
      exponent[e] = x;
      smallest = std::min(smallest, x);
    }
    double sum = 0.0;
    for (size_t e = 0; e < nE; ++e)
    {
      scaled[e] = m_Weights[e] * std::exp(smallest - exponent[e]);
      sum += scaled[e];
    }
    const double minusLogT = smallest - std::log(sum);
    const double T = std::exp(-minusLogT);
    // Standard error of -ln T: sqrt(h^T C h), h_m = (dT/dL_m) / T = -sum_E scaled_E k_m(E) / sum.
    double relativeError = 0.0;
    if (covariance)
    {
      for (unsigned int m = 0; m < K; ++m)
      {
        double g = 0.0;
        for (size_t e = 0; e < nE; ++e)
        {
          g += scaled[e] * m_Ratios[m * nE + e];
        }
        h[m] = -g / sum;
      }
      double variance = 0.0;
      for (unsigned int m = 0; m < K; ++m)
      {
        for (unsigned int n = 0; n < K; ++n)
        {
          variance += h[m] * C[m * K + n] * h[n];
        }
      }
      relativeError = std::sqrt(std::max(0.0, variance));
    }
    out.Set(static_cast<OutputPixelType>(m_OutputTransmission ? T : minusLogT));
    error.Set(static_cast<OutputPixelType>(m_OutputTransmission ? T * relativeError : relativeError));
  }
}

template <typename TChannelImage, typename TOutputImage>
void
DRRPolychromaticImageFilter<TChannelImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "MaterialTable: " << (m_MaterialTable ? "" : "(none)") << std::endl;
  if (m_MaterialTable)
  {
    m_MaterialTable->Print(os, indent.GetNextIndent());
  }
  os << indent << "Spectrum: " << (m_Spectrum ? "" : "(none)") << std::endl;
  if (m_Spectrum)
  {
    m_Spectrum->Print(os, indent.GetNextIndent());
  }
  os << indent << "ReferenceEnergyInKeV: " << m_ReferenceEnergyInKeV << std::endl;
  os << indent << "OutputTransmission: " << m_OutputTransmission << std::endl;
  os << indent << "CorrectJensenBias: " << m_CorrectJensenBias << std::endl;
  os << indent << "Covariance input: " << (this->GetCovarianceInput() ? "set" : "none") << std::endl;
}
} // namespace itk

#endif
