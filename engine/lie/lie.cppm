// keel.lie — the curated facade of engine/lie (thesis ch. 5): Lie groups SO(2), SO(3), SE(2), SE(3);
// uncertain poses in the left-perturbation convention T = exp(ξ^) T̄ (eq. 5.14), jointly distributed sets
// (eqs. 5.28–5.29) and their composition / inverse / relative pose with and without cross-covariance; SSC
// baselines (§5.3); the unscented conversion (§5.8.1); metrics. (The Monte-Carlo studies of chapter 5 are
// keel.study's.) Facade rules (docs/DESIGN.md): includes in the global module fragment, using-declarations in
// the export block, no import of another facade.
module;
#include "lie/concepts.hpp"
#include "lie/euler.hpp"
#include "lie/fourth_order_joint.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"
#include "lie/so2.hpp"
#include "lie/so3.hpp"
#include "lie/ssc.hpp"
#include "lie/types.hpp"
#include "lie/uncertain.hpp"
#include "lie/unscented.hpp"
export module keel.lie;

export namespace keel::lie {
// linear-algebra aliases and constants
using keel::lie::kPi;
using keel::lie::Mat12;
using keel::lie::Mat2;
using keel::lie::Mat3;
using keel::lie::Mat4;
using keel::lie::Mat6;
using keel::lie::MatX;
using keel::lie::Vec2;
using keel::lie::Vec3;
using keel::lie::Vec6;
using keel::lie::VecX;
// groups
using keel::lie::LieGroup;
using keel::lie::SE2;
using keel::lie::SE3;
using keel::lie::SO2;
using keel::lie::SO3;
// Euler parameters of eq. 5.15
using keel::lie::rotation_from_rpy;
using keel::lie::rpy_from_rotation;
using keel::lie::se2_from_ssc;
using keel::lie::se3_from_ssc;
using keel::lie::ssc_from_se2;
using keel::lie::ssc_from_se3;
using keel::lie::wrap_angle;
// uncertain poses and operations
using keel::lie::append_composition;
using keel::lie::append_inverse;
using keel::lie::append_relative;
using keel::lie::chain_cross_order_from_string;
using keel::lie::chain_jacobian;
using keel::lie::ChainCrossOrder;
using keel::lie::compose;
using keel::lie::compose_chain;
using keel::lie::compose_chain_fourth_order;
using keel::lie::compose_chain_fourth_order_joint;
using keel::lie::compose_chain_fourth_order_joint_exact;
using keel::lie::compose_fourth_order;
using keel::lie::compose_fourth_order_joint;
using keel::lie::inverse;
using keel::lie::JointPoses;
using keel::lie::perturb;
using keel::lie::perturbation_of;
using keel::lie::relative;
using keel::lie::to_string;
using keel::lie::UncertainPose;
// Gaussian helpers, unscented transform, metrics
using keel::lie::chi2_cdf;
using keel::lie::chi2_quantile;
using keel::lie::covariance_error;
using keel::lie::covariance_square_root;
using keel::lie::fraction_inside;
using keel::lie::joint_poses_from_ssc;
using keel::lie::mahalanobis_squared;
using keel::lie::normalized_covariance_error;
using keel::lie::sample_covariance_about_zero;
using keel::lie::unscented_transform;
using keel::lie::UtParams;
using keel::lie::UtResult;
using keel::lie::validate_covariance;
// the SSC covariance of a left-perturbed planar pose (§5.9.2)
using keel::lie::ssc_jacobian_of_left_perturbation;
}  // namespace keel::lie

// SSC operations (§5.3) keep their own namespace: keel::lie::ssc::head_to_tail, ...
export namespace keel::lie::ssc {
using keel::lie::ssc::Estimate2D;
using keel::lie::ssc::Estimate3D;
using keel::lie::ssc::head_to_tail;
using keel::lie::ssc::head_to_tail_chain_2d;
using keel::lie::ssc::head_to_tail_chain_3d;
using keel::lie::ssc::inverse;
using keel::lie::ssc::tail_to_tail;
}  // namespace keel::lie::ssc
