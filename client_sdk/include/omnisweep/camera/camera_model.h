// CameraModel<Scalar>: any supported projection model behind one value type.
//
// Each model is a small header-only class (double_sphere_camera.h, kannala_brandt_camera.h,
// extended_unified_camera.h, pinhole_camera.h) with the same members: kName, kParamNames,
// project, unproject, max_angle, scaled, check and cast. Adding a model means writing one such
// class and listing it in CameraModelVariant; calibration I/O and tests pick it up by name.
#pragma once

#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "omnisweep/camera/double_sphere_camera.h"
#include "omnisweep/camera/extended_unified_camera.h"
#include "omnisweep/camera/kannala_brandt_camera.h"
#include "omnisweep/camera/pinhole_camera.h"

namespace omnisweep {

template <typename Scalar>
using CameraModelVariant = std::variant<DoubleSphereCamera<Scalar>, KannalaBrandtCamera<Scalar>,
                                        ExtendedUnifiedCamera<Scalar>, PinholeCamera<Scalar>>;

template <typename Scalar = double>
class CameraModel {
 public:
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;

  CameraModel() = default;
  template <typename Model>
  requires std::is_constructible_v<CameraModelVariant<Scalar>, Model> CameraModel(
      const Model& model)
      : model_(model) {}  // NOLINT: implicit by design

  // The model called `name` (basalt's camera_type) with parameters in kParamNames order.
  // Throws std::invalid_argument for an unknown name or a wrong parameter count.
  static CameraModel from_params(std::string_view name, std::span<const Scalar> params) {
    std::optional<CameraModel> result;
    for_each_model([&](auto tag) {
      using Model = decltype(tag);
      if (Model::kName != name) return;
      if (params.size() != std::size_t(Model::kNumParams)) {
        throw std::invalid_argument("camera model '" + std::string(name) + "' takes " +
                                    std::to_string(Model::kNumParams) + " parameters, got " +
                                    std::to_string(params.size()));
      }
      typename Model::Params p;
      for (int i = 0; i < Model::kNumParams; ++i) p[i] = params[i];
      result = CameraModel(Model(p));
    });
    if (!result) {
      throw std::invalid_argument("unknown camera model '" + std::string(name) +
                                  "' (known: " + known_names() + ")");
    }
    return *result;
  }

  // Names of the parameters of the model called `name`; empty when unknown.
  static std::vector<std::string_view> param_names(std::string_view name) {
    std::vector<std::string_view> names;
    for_each_model([&](auto tag) {
      using Model = decltype(tag);
      if (Model::kName == name) names.assign(Model::kParamNames.begin(), Model::kParamNames.end());
    });
    return names;
  }

  static std::string known_names() {
    std::string names;
    for_each_model([&](auto tag) {
      if (!names.empty()) names += ", ";
      names += decltype(tag)::kName;
    });
    return names;
  }

  std::string_view name() const {
    return std::visit([](const auto& m) { return std::string_view(m.kName); }, model_);
  }
  std::vector<std::string_view> param_names() const { return param_names(name()); }
  std::vector<Scalar> params() const {
    return std::visit(
        [](const auto& m) { return std::vector<Scalar>(m.params().begin(), m.params().end()); },
        model_);
  }
  Scalar fx() const { return params()[0]; }
  Scalar fy() const { return params()[1]; }
  Scalar cx() const { return params()[2]; }
  Scalar cy() const { return params()[3]; }

  bool project(const Vec3& p, Vec2* uv) const {
    return std::visit([&](const auto& m) { return m.project(p, uv); }, model_);
  }
  bool unproject(const Vec2& uv, Vec3* ray) const {
    return std::visit([&](const auto& m) { return m.unproject(uv, ray); }, model_);
  }
  // Half of the model's field of view, in radians from the optical axis.
  Scalar max_angle() const {
    return std::visit([](const auto& m) { return m.max_angle(); }, model_);
  }
  Scalar field_of_view() const { return Scalar(2) * max_angle(); }

  // The same camera for an image resized by sx, sy (new / original), pixel-centre convention.
  CameraModel scaled(Scalar sx, Scalar sy) const {
    return std::visit([&](const auto& m) { return CameraModel(m.scaled(sx, sy)); }, model_);
  }
  std::optional<ParamIssue> check() const {
    return std::visit([](const auto& m) { return m.check(); }, model_);
  }
  template <typename Other>
  CameraModel<Other> cast() const {
    return std::visit([](const auto& m) { return CameraModel<Other>(m.template cast<Other>()); },
                      model_);
  }

  const CameraModelVariant<Scalar>& variant() const { return model_; }

 private:
  template <typename F>
  static void for_each_model(F&& f) {
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      (f(std::variant_alternative_t<I, CameraModelVariant<Scalar>>()), ...);
    }
    (std::make_index_sequence<std::variant_size_v<CameraModelVariant<Scalar>>>());
  }

  CameraModelVariant<Scalar> model_;
};

}  // namespace omnisweep
