#include "sysid/online/online_identifier.hpp"

#include "timeseries/gap_rule.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace odonata::sysid {

OnlineIdentifier::OnlineIdentifier(NarxModel model, RefitSchedule refit)
    : model_(std::move(model)), arx_(model_.scaling()), refitter_(refit) {}

void OnlineIdentifier::RestartHistory() {
  history_.clear();
  free_history_.clear();
  arx_free_history_.clear();
  have_last_ = false;
  resume_after_ = -1;  // a new run: its indices start again
}

void OnlineIdentifier::ReplaceModel(NarxModel model, int64_t samples_learned,
                                    int64_t learned_through) {
  model_ = std::move(model);
  settling_.Clear();
  intervals_.Clear();
  arx_ = RecursiveArx(model_.scaling());
  samples_learned_ = samples_learned;
  refitter_.Clear();  // rows learned by the model that is gone
  RestartHistory();
  resume_after_ = learned_through;
}

void OnlineIdentifier::Freeze() {
  if (learning_) refitter_.BeginClosing(model_);
  learning_ = false;
}

std::string OnlineIdentifier::FailedRefitsText() const {
  const std::string& why = refitter_.last_failure();
  return "(" + std::to_string(refitter_.failed()) + " failed" + (why.empty() ? "" : ": " + why) +
         ")";
}

void OnlineIdentifier::set_ahead_horizon(int horizon) {
  if (horizon < 0 || horizon == 1)
    throw std::invalid_argument("the horizon must be 0 (none) or K >= 2 steps ahead, not " +
                                std::to_string(horizon));
  ahead_horizon_ = horizon;
}

void OnlineIdentifier::SetForgetting(double lambda) {
  for (int o = 0; o < model_.outputs(); ++o) model_.mutable_model(o).set_forgetting(lambda);
}

void OnlineIdentifier::SetEntropyThreshold(double h) {
  for (int o = 0; o < model_.outputs(); ++o) model_.mutable_model(o).set_entropy_threshold(h);
}

void OnlineIdentifier::SettleRefit() {
  if (refitter_.Settle(model_)) Landed();
}

void OnlineIdentifier::Landed() {
  settling_.Rebuild(model_, refitter_.KeptSeries());
  if (auto seed = refitter_.TakeLandedCalibration()) intervals_.Seed(*seed, ahead_horizon_);
}

std::optional<SampleReport> OnlineIdentifier::Push(const Sample& s, PushResult* result) {
  const RegressorSpec& spec = model_.spec();
  SettleRefit();  // a closing refit takes over before the next prediction
  auto set = [result](PushResult r) {
    if (result) *result = r;
  };
  if (s.outputs.size() != static_cast<Eigen::Index>(spec.outputs.size()) ||
      s.inputs.size() != static_cast<Eigen::Index>(spec.inputs.size()) || !s.outputs.allFinite() ||
      !s.inputs.allFinite()) {
    set(PushResult::kRejected);
    return std::nullopt;
  }
  if (have_last_ && s.index <= last_index_) {
    set(PushResult::kDuplicate);
    return std::nullopt;
  }
  if (resume_after_ >= 0) {
    if (s.index <= resume_after_) {
      ++already_learned_;
      set(PushResult::kDuplicate);
      return std::nullopt;
    }
    // The samples the identifier was down for (or learned after its last snapshot and lost
    // with it): gaps, as any other samples that never came.
    const int64_t missing = s.index - resume_after_ - 1;
    resume_after_ = -1;
    gaps_ += missing;
    missed_on_resume_ += missing;
    set(missing > 0 ? PushResult::kGap : PushResult::kAccepted);
    return Step(s);
  }
  set(PushResult::kAccepted);
  if (have_last_ && s.index != last_index_ + 1) {
    const int64_t missing = s.index - last_index_ - 1;
    gaps_ += missing;
    if (timeseries::Bridges(missing, max_gap_) && !history_.empty()) {
      // The straight line from the newest sample to this one, by odonata-fit's own gap rule
      // (timeseries/gap_rule.hpp), so a lossy real-time run learns what odonata-fit learns from
      // the exported log instead of warming up again for ny samples.
      const Sample a = history_.back();
      for (int64_t k = 1; k <= missing; ++k) {
        Sample b;
        b.index = a.index + k;
        b.outputs = timeseries::Bridge<Eigen::VectorXd>(a.outputs, s.outputs, k, missing + 1);
        b.inputs = timeseries::Bridge<Eigen::VectorXd>(a.inputs, s.inputs, k, missing + 1);
        Step(b);
        ++bridged_;
      }
      set(PushResult::kBridged);
    } else {
      history_.clear();
      free_history_.clear();
      arx_free_history_.clear();
      set(PushResult::kGap);
    }
  }
  return Step(s);
}

std::optional<SampleReport> OnlineIdentifier::Step(const Sample& s) {
  const RegressorSpec& spec = model_.spec();
  have_last_ = true;
  last_index_ = s.index;

  const auto t0 = static_cast<std::size_t>(spec.first_target());
  history_.push_back(s);
  if (learning_) refitter_.Keep(s);
  // The free run starts from measured outputs; once running, each entry is replaced by the
  // model's own simulation of that sample.
  free_history_.push_back(s.outputs);
  arx_free_history_.push_back(s.outputs);
  // K-step predictions need the last K samples besides the regressor's lags.
  while (history_.size() > t0 + static_cast<std::size_t>(std::max(ahead_horizon_, 1))) {
    history_.pop_front();
    free_history_.pop_front();
    arx_free_history_.pop_front();
  }
  if (history_.size() < t0 + 1) return std::nullopt;

  const auto n = static_cast<Eigen::Index>(history_.size());
  const auto no = static_cast<Eigen::Index>(spec.outputs.size());
  Eigen::MatrixXd y(n, no), f(n, no), fa(n, no),
      u(n, static_cast<Eigen::Index>(spec.inputs.size()));
  for (Eigen::Index r = 0; r < n; ++r) {
    const auto i = static_cast<std::size_t>(r);
    y.row(r) = history_[i].outputs.transpose();
    f.row(r) = free_history_[i].transpose();
    fa.row(r) = arx_free_history_[i].transpose();
    u.row(r) = history_[i].inputs.transpose();
  }

  SampleReport rep;
  rep.index = s.index;
  rep.measured = s.outputs;
  const Eigen::Index t = n - 1;
  Eigen::VectorXd x(spec.size());
  // A diverging output holds the last value of its own history rather than poisoning
  // everything with NaN.
  const auto hold_at = [&](Eigen::Index r, Eigen::VectorXd v, const Eigen::MatrixXd& past) {
    for (Eigen::Index o = 0; o < no; ++o)
      if (!std::isfinite(v(o))) v(o) = r > 0 ? past(r - 1, o) : y(r, o);
    return v;
  };
  const auto hold = [&](Eigen::VectorXd v, const Eigen::MatrixXd& past) {
    return hold_at(t, std::move(v), past);
  };
  if (ahead_horizon_ >= 2) {
    // ŷ(k | k−K) by the model in force now, as PredictAhead computes it offline: measured
    // outputs up to k−K (or the segment's start), then the model's own predictions.
    const Eigen::Index first =
        std::max<Eigen::Index>(static_cast<Eigen::Index>(t0), n - ahead_horizon_);
    Eigen::MatrixXd g = y, ga = y;
    for (Eigen::Index r = first; r < n; ++r) {
      spec.Fill(r, g, u, x);
      g.row(r) = hold_at(r, model_.Predict(x), g).transpose();
      spec.Fill(r, ga, u, x);
      ga.row(r) = hold_at(r, arx_.Predict(x), ga).transpose();
    }
    rep.ahead = g.row(t).transpose();
    rep.arx_ahead = ga.row(t).transpose();
    rep.horizon = ahead_horizon_;
  }
  // The free run's regressor is filled here, after the K-step predictions, which reuse x: filled
  // before them, the free run read the live ARX's K-step trajectory instead of its own past.
  spec.Fill(t, f, u, x);
  rep.free_run = hold(model_.Predict(x), f);
  free_history_.back() = rep.free_run;
  spec.Fill(t, fa, u, x);
  rep.arx_free_run = hold(arx_.Predict(x), fa);
  arx_free_history_.back() = rep.arx_free_run;

  spec.Fill(t, y, u, x);
  rep.predicted = model_.Predict(x, &rep.linear_share);
  ++predicted_;
  if ((rep.linear_share.array() > 0.0).any()) ++outside_;
  rep.arx_predicted = hold(arx_.Predict(x), y);
  // The baseline learns what the fuzzy model learns, and nothing when frozen (a fair validation).
  if (learning_) arx_.Update(x, s.outputs);
  if (learning_) settling_.Observe(model_, x, s.outputs, rep.predicted);
  // The intervals of sample k come from earlier samples' residuals; then k's own joins them.
  const auto widths = [no](const Eigen::VectorXd& w) {
    return w.size() == no ? w
                          : Eigen::VectorXd::Constant(no, std::numeric_limits<double>::infinity());
  };
  rep.interval_level = intervals_.level();
  rep.half_width = widths(intervals_.one_step());
  if (rep.ahead.size() > 0) rep.ahead_half_width = widths(intervals_.ahead());
  rep.free_run_half_width = widths(intervals_.free_run());
  if (learning_) intervals_.Add(s.outputs, rep.predicted, rep.ahead, rep.free_run);
  rep.seen_enough = settling_.States(model_);
  rep.rules.resize(no);
  rep.max_entropy.resize(no);
  // Once a scheduled refit has landed the refits own the model (scheduled_refitter.hpp).
  const bool per_sample = learning_ && !refitter_.owns_model();
  const auto results = model_.Learn(
      x, s.outputs, per_sample ? fuzzy::LearnMode::kGrowAndTune : fuzzy::LearnMode::kFrozen);
  // Between refits the model tracks by recursive global least squares, continued from the last
  // refit (ConsequentTracker): one learner, its least-squares problem one row longer.
  if (learning_ && !per_sample) refitter_.Track(model_, x, s.outputs);
  for (Eigen::Index o = 0; o < no; ++o) {
    rep.max_entropy(o) = results[static_cast<std::size_t>(o)].max_entropy;
    rep.rules(o) = model_.model(static_cast<int>(o)).rules();
  }
  rep.learned = learning_;
  if (learning_) {
    ++samples_learned_;
    if (refitter_.AfterLearn(model_, samples_learned_)) Landed();
  }

  rep.next = Eigen::VectorXd::Constant(no, std::numeric_limits<double>::quiet_NaN());
  if (spec.delay == 1) {
    // x(k+1) needs y(k) … and u(k) …: all known now. Shift by appending a dummy row.
    Eigen::MatrixXd y1(n + 1, no), u1(n + 1, u.cols());
    y1.topRows(n) = y;
    y1.row(n).setZero();
    u1.topRows(n) = u;
    u1.row(n).setZero();
    spec.Fill(n, y1, u1, x);
    rep.next = model_.Predict(x);
  }
  return rep;
}

}  // namespace odonata::sysid

namespace odonata::sysid {

OnlineReplay LearnOnline(NarxModel model, const RefitSchedule& refit, const Series& series,
                         const std::optional<Scaling>& scaling, bool frozen) {
  if (scaling)
    model.SetScaling(*scaling);
  else
    model.FitScaling(series);
  OnlineIdentifier id(std::move(model), refit);
  std::size_t next_break = 0;
  int64_t index = 0;
  for (Eigen::Index r = 0; r < series.samples(); ++r) {
    if (next_break < series.breaks.size() && series.breaks[next_break] == r) {
      ++index;  // a skipped index: the identifier's history restarts, as at a gap
      ++next_break;
    }
    Sample s;
    s.index = index++;
    s.outputs = series.outputs.row(r).transpose();
    s.inputs = series.inputs.row(r).transpose();
    id.Push(s);
  }
  if (frozen) {
    id.Freeze();
    id.Settle();
  }
  return OnlineReplay{id.model(),           id.refits(),          id.failed_refits(),
                      id.samples_learned(), id.incumbents_kept(), id.steady_state_refused(),
                      id.linear_landed(),   id.Settling()};
}

}  // namespace odonata::sysid
