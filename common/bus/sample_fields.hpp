#pragma once
// Named signals of the command and state messages. The names are odonata-sim's CSV columns, so
// a signal is called the same in a config file, a CSV file and on the bus.

#include <optional>
#include <string>
#include <vector>

#include "odonata/beat_state_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/wing_command_t.hpp"

namespace odonata::bus {

/// "w1_beta_rad" … "w4_phase_rad" (24 names, odonata-sim's order).
const std::vector<std::string>& CommandFieldNames();
/// "vx_mps" … "z_m", "fx1_n" … "fz4_n" (odonata-sim's order).
const std::vector<std::string>& StateFieldNames();

/// The beat averages of beat_state_t, named as odonata-sim's columns: "vx_mps_avg" …
/// "yaw_rad_avg", "fx_total_n_avg", "fz_total_n_avg".
const std::vector<std::string>& BeatFieldNames();
/// The applied-command channels of beat_state_t: "u_vertical_applied_rad", "u_roll_applied_rad",
/// "u_pitch_applied_rad", "u_yaw_applied_rad". Beat state k + 1 carries the command applied over
/// [t_k, t_k+1), so they belong with sample k's command (as in odonata-sim's row k).
const std::vector<std::string>& AppliedFieldNames();
/// Which beat state holds a beat-state signal of sample k, as an offset from k: 0 for the beat
/// averages (BeatFieldNames(): beat state k, up to t_k, like state k), 1 for the applied-command
/// channels (AppliedFieldNames(): beat state k + 1, the command applied over [t_k, t_k+1)).
/// nullopt when `name` is neither.
std::optional<int> BeatStateOffset(const std::string& name);

/// True for a signal that holds over [t_k, t_k+1) — a command field, an excitation, an applied
/// channel — which decimation averages over a block; false for a measurement at t_k (a state
/// field, a beat average, "t_s"), which it takes at the block's first sample.
bool IsAveragedSignal(const std::string& name);

/// The value of a named command field or excitation; nullopt when the name is unknown.
std::optional<double> CommandField(const odonata::wing_command_t& msg, const std::string& name);
/// The value of a named state field; nullopt when the name is unknown.
std::optional<double> StateField(const odonata::plant_state_t& msg, const std::string& name);
/// The value of a named beat average or applied channel (or "t_s", "window_s"); nullopt when
/// the name is unknown.
std::optional<double> BeatStateField(const odonata::beat_state_t& msg, const std::string& name);

/// True when every numeric field is finite (NaN or Inf ⇒ the message is dropped).
bool AllFinite(const odonata::wing_command_t& msg);
bool AllFinite(const odonata::plant_state_t& msg);
bool AllFinite(const odonata::beat_state_t& msg);

/// Problems of the variable-length arrays (count fields disagreeing with array sizes), empty
/// when fine: encode() trusts the counts, so a bad message must never be republished.
std::string CountProblems(const odonata::wing_command_t& msg);

}  // namespace odonata::bus
