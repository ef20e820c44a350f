#pragma once
// Rules as sentences a drone operator can read and check against intuition.

#include <string>
#include <vector>

#include "sysid/model/local_dynamics.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

/// Linguistic label of a scaled centre c ∈ [−1, 1] (the input's training range): five equal
/// bands "very low", "low", "medium", "high", "very high"; outside the range "below range" /
/// "above range" so an extrapolating rule is visible as such.
std::string LinguisticLabel(double scaled_centre);

/// One sentence per rule of output `output`, e.g.
/// "IF y(k) is high (≈0.82 ±0.3) AND u(k) is low (≈-1.1 ±0.2) THEN y(k+1) is ≈0.64", in raw
/// units; a linear consequent prints as "THEN y(k+1) ≈ 0.31 + 0.92·y(k) - 0.10·u(k)", and with
/// output lags its dynamics follow ("— τ 0.12 s, gain 31 from u": DescribeDynamics), time in
/// seconds with `sample_time_s`, else in samples.
std::vector<std::string> DescribeRules(const NarxModel& model, int output,
                                       double sample_time_s = 0);

/// A linear local model of output `output` as its sentence's right-hand side:
/// "0.31 + 0.92·y(k) - 0.10·u(k)", and with output lags " — " and its dynamics
/// (DescribeDynamics). The full rules and the readable form (readable_model.hpp) both print it.
std::string DescribeLinearModel(const RegressorSpec& spec, int output, const RawLinearModel& raw,
                                double sample_time_s);

}  // namespace odonata::sysid
