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
#ifndef PointBasedDRRWrappedSetTest_h
#define PointBasedDRRWrappedSetTest_h

// What the generated test of the wrapped set (GenerateWrappedSetTest.cmake) runs for each class or template instance
// the .wrap files name: Exercise<T>(className). By kind of class:
// - an image filter (itk::ProcessObject): renders a 4 x 3 x 2 volume on a 5 x 4 detector (2000 points) and checks the
//   size and finiteness of the output (and of the standard-error output);
// - an interpolator (itk::InterpolateImageFunction): one Evaluate() on that volume;
// - another itk::Object: New(), GetNameOfClass(), Print() and a setter/getter pair (samplers: Initialize() on the
//   volume's attenuation, then GetTotalMass());
// - a class that is no itk::Object: an ExerciseNonObject() overload below (a new one fails to compile without).
// A class without its own New() (abstract) is run through the concrete class StandIn<T> names (a new one fails to
// compile without). Every test also checks that each base class, up to one ITK wraps itself, is wrapped here: SWIG
// needs the base classes of a wrapped class wrapped.

#include "itkDRRCompatibility.h"
#include "itkDRRLevelAliasSampler.h"
#include "itkDRRMetropolisSampler.h"
#include "itkDRRPaperHybridSampler.h"
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkDRRProjectionMatrixFileIO.h"
#include "itkDRRQuantumNoiseImageFilter.h"
#include "itkDRRSamplerFactory.h"
#include "itkExactDRRImageFilter.h"
#include "itkIdentityTransform.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkInterpolateImageFunction.h"
#include "itkPointBasedDRRImageFilter.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <cxxabi.h>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>

namespace PointBasedDRRWrappedSet
{
/** Wrapped by the module's .wrap files; wrapped by ITK's own modules (both specialized by the generated test). */
template <typename T>
struct WrappedHere : std::false_type
{};
template <typename T>
struct WrappedByITK : std::false_type
{};

template <typename T>
struct AlwaysFalse : std::false_type
{};

/** The concrete class a wrapped class without its own New() is run through. */
template <typename T>
struct StandIn
{
  static_assert(AlwaysFalse<T>::value,
                "a wrapped class without its own New() needs a StandIn<> in PointBasedDRRWrappedSetTest.h");
};
template <typename TInputImage, typename TOutputImage>
struct StandIn<itk::ImageToImageFilter<TInputImage, TOutputImage>>
{
  using Type = itk::ExactDRRImageFilter<TInputImage, TOutputImage>;
};
template <typename TInputImage, typename TOutputImage>
struct StandIn<itk::DRRImageFilterBase<TInputImage, TOutputImage>>
{
  using Type = itk::ExactDRRImageFilter<TInputImage, TOutputImage>;
};
template <>
struct StandIn<itk::DRRPointSampler>
{
  using Type = itk::DRRLevelAliasSampler;
};
template <>
struct StandIn<itk::DRRLevelSampler>
{
  using Type = itk::DRRLevelAliasSampler;
};

/** True if T::New() is T's own (not one inherited from itk::Object or itk::LightObject). */
template <typename T, typename = void>
struct HasOwnNew : std::false_type
{};
template <typename T>
struct HasOwnNew<T, std::void_t<decltype(T::New())>> : std::is_same<decltype(T::New()), itk::SmartPointer<T>>
{};

template <typename T, bool = HasOwnNew<T>::value>
struct Concrete
{
  using Type = T;
};
template <typename T>
struct Concrete<T, false>
{
  using Type = typename StandIn<T>::Type;
};

template <typename T, typename = void>
struct HasSuperclass : std::false_type
{};
template <typename T>
struct HasSuperclass<T, std::void_t<typename T::Superclass>> : std::true_type
{};

template <typename T, typename = void>
struct IsInterpolator : std::false_type
{};
template <typename T>
struct IsInterpolator<T, std::void_t<typename T::InputImageType, itk::DRRCoordinateTypeOf<T>>>
  : std::is_base_of<itk::InterpolateImageFunction<typename T::InputImageType, itk::DRRCoordinateTypeOf<T>>, T>
{};

/** The quantum-noise filter: an image filter of line integrals, with no geometry. */
template <typename T>
struct IsQuantumNoise : std::false_type
{};
template <typename TImage>
struct IsQuantumNoise<itk::DRRQuantumNoiseImageFilter<TImage>> : std::true_type
{};

template <typename T>
std::string
TypeName()
{
  int                                     status = 0;
  std::unique_ptr<char, void (*)(void *)> name(abi::__cxa_demangle(typeid(T).name(), nullptr, nullptr, &status),
                                               std::free);
  return status == 0 ? std::string(name.get()) : std::string(typeid(T).name());
}

/** The first base class of T, up to one ITK wraps, that is not wrapped; empty if none. */
template <typename T>
std::string
FirstUnwrappedSuperclass()
{
  if constexpr (!HasSuperclass<T>::value)
  {
    return {};
  }
  else
  {
    using SuperclassType = typename T::Superclass;
    if constexpr (WrappedByITK<SuperclassType>::value)
    {
      return {};
    }
    else if constexpr (WrappedHere<SuperclassType>::value)
    {
      return FirstUnwrappedSuperclass<SuperclassType>();
    }
    else
    {
      return TypeName<SuperclassType>();
    }
  }
}

/** A 4 x 3 x 2 volume of 1.5 x 1 x 2 mm voxels centred on the origin: 100 HU, one voxel of 250 HU (any pixel type). */
template <typename TVolume>
typename TVolume::Pointer
MakeVolume()
{
  auto                             volume = TVolume::New();
  const typename TVolume::SizeType size = { { 4, 3, 2 } };
  typename TVolume::SpacingType    spacing;
  typename TVolume::PointType      origin;
  const double                     voxel[3] = { 1.5, 1.0, 2.0 };
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    spacing[axis] = voxel[axis];
    origin[axis] = -0.5 * (size[axis] - 1) * voxel[axis];
  }
  volume->SetRegions(size);
  volume->SetSpacing(spacing);
  volume->SetOrigin(origin);
  volume->Allocate();
  volume->FillBuffer(100);
  volume->SetPixel({ { 1, 1, 0 } }, 250);
  return volume;
}

constexpr unsigned int DetectorColumns = 5;
constexpr unsigned int DetectorRows = 4;

/** A 5 x 4 detector of 2 mm pixels, the default perspective geometry (gantry 0, SAD 1000 mm, SID 1500 mm). */
inline itk::DRRProjectionGeometry::Pointer
MakeGeometry()
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetDetectorSize({ { DetectorColumns, DetectorRows } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(2.0));
  geometry->VerifyGeometry();
  return geometry;
}

/** The output is the detector's size (5 x 4, or 5 x 4 x 1) and finite; a line-integral image is positive somewhere. */
template <typename TImage>
void
ExpectProjection(const TImage * image, const std::string & what, bool positive)
{
  ASSERT_NE(image, nullptr) << what;
  const auto size = image->GetLargestPossibleRegion().GetSize();
  EXPECT_EQ(size[0], DetectorColumns) << what;
  EXPECT_EQ(size[1], DetectorRows) << what;
  if constexpr (TImage::ImageDimension == 3)
  {
    EXPECT_EQ(size[2], 1u) << what;
  }
  double sum = 0.0;
  // With index: ImageConstIterator::GetIndex() is deprecated in ITK 6 (ComputeIndex(), which 5.4 and 5.2 lack).
  for (itk::ImageRegionConstIteratorWithIndex<TImage> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    ASSERT_TRUE(std::isfinite(static_cast<double>(it.Get()))) << what << " at " << it.GetIndex();
    EXPECT_GE(it.Get(), 0) << what << " at " << it.GetIndex();
    sum += it.Get();
  }
  if (positive)
  {
    EXPECT_GT(sum, 0.0) << what;
  }
}

/** Runs the quantum-noise filter once on line integrals of 1: finite noisy line integrals, its settings printed. */
template <typename T>
void
RunQuantumNoise(const std::string & className)
{
  using ImageType = typename T::ImageType;
  auto                         image = ImageType::New();
  typename ImageType::SizeType size;
  size.Fill(8);
  image->SetRegions(size);
  image->Allocate();
  image->FillBuffer(1.0f);
  auto filter = T::New();
  filter->SetInput(image);
  filter->SetNumberOfPhotons(1000.0);
  filter->SetSeed(3);
  EXPECT_NO_THROW(filter->Update()) << className;
  double sum = 0.0;
  for (itk::ImageRegionConstIterator<ImageType> it(filter->GetOutput(), filter->GetOutput()->GetBufferedRegion());
       !it.IsAtEnd();
       ++it)
  {
    EXPECT_TRUE(std::isfinite(it.Get())) << className;
    sum += it.Get();
  }
  EXPECT_NEAR(sum / static_cast<double>(image->GetBufferedRegion().GetNumberOfPixels()), 1.0, 0.1) << className;
  std::ostringstream printed;
  filter->Print(printed);
  EXPECT_NE(printed.str().find("NumberOfPhotons"), std::string::npos) << className << " Print():\n" << printed.str();
}

/** Runs an image filter once, through the wrapped class's own interface (ImageToImageFilter's for a base class). */
/** The preprocessing stage: a volume in, the attenuation model out, which a DRR filter renders as its own. */
template <typename T, typename = void>
struct IsAttenuationVolumeFilter : std::false_type
{};
template <typename T>
struct IsAttenuationVolumeFilter<T, std::void_t<typename T::InputImageType>>
  : std::is_base_of<itk::DRRImageToAttenuationVolumeFilter<typename T::InputImageType>, T>
{};

template <typename T>
void
RunAttenuationVolumeFilter(const std::string & className)
{
  using VolumeType = typename T::InputImageType;
  using DRRType = itk::ExactDRRImageFilter<VolumeType, itk::Image<float, 2>>;
  auto stage = T::New();
  stage->SetInput(MakeVolume<VolumeType>());
  EXPECT_NO_THROW(stage->Update()) << className;
  EXPECT_EQ(stage->GetOutput()->GetNumberOfVoxels(), 24u) << className;
  EXPECT_GT(stage->GetOutput()->ComputeTotalMass(), 0.0) << className;
  auto shared = DRRType::New();
  shared->SetGeometry(MakeGeometry());
  shared->SetAttenuationVolume(stage->GetOutput());
  auto own = DRRType::New();
  own->SetGeometry(MakeGeometry());
  own->SetInput(stage->GetInput());
  shared->Update();
  own->Update();
  const size_t pixels = shared->GetOutput()->GetBufferedRegion().GetNumberOfPixels();
  EXPECT_TRUE(std::equal(shared->GetOutput()->GetBufferPointer(),
                         shared->GetOutput()->GetBufferPointer() + pixels,
                         own->GetOutput()->GetBufferPointer()))
    << className << ": a shared model renders as a filter's own";
  std::ostringstream printed;
  stage->Print(printed);
  EXPECT_NE(printed.str().find("TransferFunction"), std::string::npos) << className << " Print():\n" << printed.str();
}

template <typename T>
void
RunImageFilter(const std::string & className)
{
  using ConcreteType = typename Concrete<T>::Type;
  using PointBasedType = itk::PointBasedDRRImageFilter<typename T::InputImageType, typename T::OutputImageType>;
  constexpr bool pointBased = std::is_base_of<PointBasedType, ConcreteType>::value;
  auto           concrete = ConcreteType::New();
  concrete->SetGeometry(MakeGeometry());
  if constexpr (pointBased)
  {
    concrete->SetNumberOfSamples(2000);
    concrete->SetSeed(1);
  }
  T & filter = *concrete;
  filter.SetInput(MakeVolume<typename T::InputImageType>());
  EXPECT_NO_THROW(filter.Update()) << className;
  ExpectProjection(filter.GetOutput(), className + " output", true);
  if constexpr (pointBased)
  {
    ExpectProjection(concrete->GetStandardErrorOutput(), className + " standard error", false);
  }
  std::ostringstream printed;
  filter.Print(printed);
  EXPECT_NE(printed.str().find("Geometry"), std::string::npos) << className << " Print():\n" << printed.str();
}

/** One Evaluate() of an interpolator at the centre of the detector, as a registration metric asks it. */
template <typename T>
void
RunInterpolator(const std::string & className)
{
  auto interpolator = T::New();
  auto geometry = MakeGeometry();
  interpolator->SetInputImage(MakeVolume<typename T::InputImageType>());
  interpolator->SetTransform(itk::IdentityTransform<double, 3>::New());
  interpolator->SetFocalPoint(geometry->GetSourcePosition());
  interpolator->SetDetectorGeometry(geometry);
  interpolator->GetDRRFilter()->SetNumberOfSamples(2000);
  const double value = interpolator->Evaluate(geometry->GetPixelCenter(2.0, 1.5));
  EXPECT_TRUE(std::isfinite(value)) << className;
  EXPECT_GT(value, 0.0) << className;
  std::ostringstream printed;
  interpolator->Print(printed);
  EXPECT_FALSE(printed.str().empty()) << className;
}

/** A setter/getter pair of each kind of object; other objects: the object name. */
template <typename T>
void
ExerciseSetterGetter(T & object, const std::string & className)
{
  if constexpr (std::is_base_of<itk::DRRProjectionGeometry, T>::value)
  {
    object.SetSourceToIsocenterDistance(800.0);
    EXPECT_EQ(object.GetSourceToIsocenterDistance(), 800.0) << className;
    object.SetGantryAngleInDegrees(90.0);
    EXPECT_NEAR(object.GetNormal()[1], -1.0, 1e-12) << className;
  }
  else if constexpr (std::is_base_of<itk::DRRProjectionGeometryFileIO, T>::value ||
                     std::is_base_of<itk::DRRProjectionMatrixFileIO, T>::value)
  {
    object.SetFileName("geometry.txt");
    EXPECT_EQ(std::string(object.GetFileName()), "geometry.txt") << className;
  }
  else if constexpr (std::is_base_of<itk::DRRTransferFunction, T>::value)
  {
    object.SetMuWaterPerMillimeter(0.02);
    EXPECT_EQ(object.GetMuWaterPerMillimeter(), 0.02) << className;
    EXPECT_DOUBLE_EQ(object.Evaluate(0.0), 0.02) << className;
  }
  else if constexpr (std::is_base_of<itk::DRRPointSampler, T>::value)
  {
    if constexpr (std::is_base_of<itk::DRRLevelSampler, T>::value)
    {
      object.SetNumberOfBins(64);
      EXPECT_EQ(object.GetNumberOfBins(), 64u) << className;
    }
    if constexpr (std::is_base_of<itk::DRRMetropolisSampler, T>::value)
    {
      object.SetBurnIn(8);
      EXPECT_EQ(object.GetBurnIn(), 8u) << className;
    }
    if constexpr (std::is_base_of<itk::DRRPaperHybridSampler, T>::value)
    {
      object.SetRouletteSurvival(0.5);
      EXPECT_EQ(object.GetRouletteSurvival(), 0.5) << className;
    }
    using VolumeType = itk::Image<short, 3>;
    auto filter = itk::ExactDRRImageFilter<VolumeType, itk::Image<float, 2>>::New();
    filter->SetInput(MakeVolume<VolumeType>());
    object.Initialize(*filter->GetAttenuationVolume());
    EXPECT_GT(object.GetTotalMass(), 0.0) << className;
    EXPECT_TRUE(std::isfinite(object.GetTotalMass())) << className;
  }
  else
  {
    object.SetObjectName("wrapped");
    EXPECT_EQ(object.GetObjectName(), "wrapped") << className;
  }
}

/** New() (or the stand-in's), GetNameOfClass(), Print(), a setter/getter pair. */
template <typename T>
void
RunObject(const std::string & className, const std::string & shortName)
{
  auto concrete = Concrete<T>::Type::New();
  T &  object = *concrete;
  if constexpr (HasOwnNew<T>::value)
  {
    EXPECT_EQ(std::string(object.GetNameOfClass()), shortName) << className;
  }
  std::ostringstream printed;
  object.Print(printed);
  EXPECT_NE(printed.str().find(object.GetNameOfClass()), std::string::npos) << className << ":\n" << printed.str();
  ExerciseSetterGetter(object, className);
}

/** Classes that are no itk::Object. */
inline void
ExerciseNonObject(itk::DRRSamplerFactory *, const std::string & className)
{
  ASSERT_FALSE(itk::DRRSamplerFactory::GetEntries().empty()) << className;
  for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
  {
    const auto sampler = itk::DRRSamplerFactory::Create(entry.Name);
    ASSERT_NE(sampler, nullptr) << className << " " << entry.Name;
    EXPECT_NE(itk::DRRSamplerFactory::GetNames().find(entry.Name), std::string::npos) << className;
  }
  EXPECT_THROW(itk::DRRSamplerFactory::Create("no such sampler"), itk::ExceptionObject) << className;
}

inline void
ExerciseNonObject(itk::PointBasedDRREnums *, const std::string & className)
{
  using Enums = itk::PointBasedDRREnums;
  std::ostringstream printed;
  printed << Enums::Projection::Parallel << ' ' << Enums::ReconstructionKernel::Tent << ' ' << Enums::Splat::Bilinear
          << ' ' << Enums::OutputMode::Transmission << ' ' << Enums::TransferFunction::Identity << ' '
          << Enums::PointWeighting::PaperCount;
  EXPECT_NE(printed.str().find("Transmission"), std::string::npos) << className << ": " << printed.str();
}

template <typename T>
void
ExerciseNonObject(T *, const std::string &)
{
  static_assert(AlwaysFalse<T>::value,
                "a wrapped class that is no itk::Object needs an ExerciseNonObject() in PointBasedDRRWrappedSetTest.h");
}

/** Runs one wrapped class or template instance once. */
template <typename T>
void
Exercise(const std::string & className)
{
  EXPECT_EQ(FirstUnwrappedSuperclass<T>(), "")
    << className << ": this base class is wrapped neither by the module nor by ITK (SWIG needs it)";
  const std::string shortName = className.substr(className.rfind(':') + 1);
  if constexpr (IsInterpolator<T>::value)
  {
    RunInterpolator<T>(className);
  }
  else if constexpr (IsQuantumNoise<T>::value)
  {
    RunQuantumNoise<T>(className);
  }
  else if constexpr (IsAttenuationVolumeFilter<T>::value)
  {
    RunAttenuationVolumeFilter<T>(className);
  }
  else if constexpr (std::is_base_of<itk::ProcessObject, T>::value)
  {
    RunImageFilter<T>(className);
  }
  else if constexpr (std::is_base_of<itk::Object, T>::value)
  {
    RunObject<T>(className, shortName);
  }
  else
  {
    ExerciseNonObject(static_cast<T *>(nullptr), className);
  }
}
} // namespace PointBasedDRRWrappedSet

#endif
