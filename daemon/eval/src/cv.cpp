#include "fovea/eval/cv.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

namespace fovea::eval {

std::vector<Tunable> detector_tunables() {
    // Nothing is fitted today. pursuit_dps is the 1-deg displacement bound of the literature
    // (gaze::DetectorParams); the pursuit floor, once 85 x noise fitted as pursuit_noise_gain
    // {55, 85, 130}, is a significance level on the recording's own noise and drift
    // (pursuit_floor_sd = 3, 2026-12-06 stop 41: daemon/eval/README.md). A constant fitted on
    // data goes here with its grid, and every fold refits it without the dataset it scores.
    return {};
}

double objective(const DatasetScore& s) {
    double sum = 0;
    int n = 0;
    for (const auto& [stimulus, events] : s.cells) {
        for (const auto& [event, coders] : events) {
            const auto it = coders.find(kAllCoders);
            if (it == coders.end()) continue;
            const double k = it->second.kappa();
            if (!std::isfinite(k)) continue;
            sum += k;
            ++n;
        }
    }
    return n ? sum / n : gaze::kNaN;
}

namespace {

// Runs jobs [0, n) on `threads` threads (the calling thread is one of them).
void parallel(size_t n, int threads, const std::function<void(size_t)>& job) {
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t i; (i = next.fetch_add(1)) < n;) job(i);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
}

std::vector<Candidate> candidates(const std::vector<Tunable>& tunables,
                                  const gaze::DetectorParams& base) {
    std::vector<Candidate> out{{base, {}}};
    for (const Tunable& t : tunables) {
        std::vector<Candidate> next;
        for (const Candidate& c : out) {
            for (double v : t.grid) {
                Candidate k = c;
                k.params.*t.field = v;
                k.values.push_back(v);
                next.push_back(k);
            }
        }
        out = std::move(next);
    }
    return out;
}

}  // namespace

std::vector<std::vector<gaze::Event>> detect_all(const Dataset& d,
                                                 const gaze::DetectorParams& params,
                                                 const DetectFn& fn, int threads) {
    std::vector<std::vector<gaze::Event>> det(d.recordings.size());
    parallel(d.recordings.size(), threads, [&](size_t i) { det[i] = fn(d.recordings[i], params); });
    return det;
}

DatasetScore evaluate(const Dataset& d, const gaze::DetectorParams& params, const DetectFn& fn,
                      int threads) {
    return score(d, detect_all(d, params, fn, threads));
}

CvResult run_cv(const std::vector<Dataset>& datasets, const gaze::DetectorParams& base,
                const DetectFn& detect_fn, int threads, const std::vector<std::string>& pinned) {
    CvResult out;
    out.tunables = detector_tunables();
    std::erase_if(out.tunables, [&](const Tunable& t) {
        const bool pin = std::find(pinned.begin(), pinned.end(), t.name) != pinned.end();
        if (pin) out.pinned.emplace_back(t.name, base.*t.field);
        return pin;
    });
    for (const Tunable& t : out.tunables) out.shipped.push_back(base.*t.field);
    const std::vector<Candidate> cands = candidates(out.tunables, base);
    out.candidates = cands.size();
    size_t shipped = cands.size();
    for (size_t c = 0; c < cands.size() && shipped == cands.size(); ++c) {
        if (cands[c].values == out.shipped) shipped = c;
    }
    // The shipped setting is scored even when it is off the grid.
    std::vector<Candidate> all = cands;
    if (shipped == cands.size()) all.push_back({base, out.shipped});

    // One job per (candidate, recording), all datasets in one pool for balance.
    struct Job {
        size_t cand, dataset, recording;
    };
    std::vector<Job> jobs;
    for (size_t c = 0; c < all.size(); ++c)
        for (size_t d = 0; d < datasets.size(); ++d)
            for (size_t r = 0; r < datasets[d].recordings.size(); ++r) jobs.push_back({c, d, r});
    std::vector<std::vector<std::vector<std::vector<gaze::Event>>>> det(all.size());
    for (auto& per_cand : det) {
        per_cand.resize(datasets.size());
        for (size_t d = 0; d < datasets.size(); ++d)
            per_cand[d].resize(datasets[d].recordings.size());
    }
    parallel(jobs.size(), threads, [&](size_t i) {
        const Job& j = jobs[i];
        det[j.cand][j.dataset][j.recording] =
            detect_fn(datasets[j.dataset].recordings[j.recording], all[j.cand].params);
    });
    std::vector<std::vector<DatasetScore>> scores(all.size());
    std::vector<std::vector<double>> obj(all.size());
    for (size_t c = 0; c < all.size(); ++c) {
        for (size_t d = 0; d < datasets.size(); ++d) {
            scores[c].push_back(score(datasets[d], det[c][d]));
            obj[c].push_back(objective(scores[c].back()));
        }
        det[c].clear();
    }
    // Grid distance of a candidate from the middle of every grid: where the training folds do
    // not tell candidates apart (no labels the constant acts on), the fit takes the grid's
    // middle, a prior fixed before any data, never the shipped (in-sample) value.
    auto off_centre = [&](const Candidate& c) {
        double d = 0;
        for (size_t t = 0; t < out.tunables.size(); ++t) {
            const auto& g = out.tunables[t].grid;
            const auto at = std::find(g.begin(), g.end(), c.values[t]) - g.begin();
            d += std::fabs(static_cast<double>(at) - 0.5 * static_cast<double>(g.size() - 1));
        }
        return d;
    };
    // Best grid candidate over the human-labelled datasets except `skip` (none: all of them).
    auto fit = [&](size_t skip) {
        size_t best = 0;
        double best_v = -1e300;
        for (size_t c = 0; c < cands.size(); ++c) {
            double sum = 0;
            int n = 0;
            for (size_t d = 0; d < datasets.size(); ++d) {
                if (d == skip || !datasets[d].human || !std::isfinite(obj[c][d])) continue;
                sum += obj[c][d];
                ++n;
            }
            const double v = n ? sum / n : -1e300;
            const bool tie = std::fabs(v - best_v) <= 1e-9;
            if ((!tie && v > best_v) || (tie && off_centre(cands[c]) < off_centre(cands[best]))) {
                best_v = v;
                best = c;
            }
        }
        return best;
    };
    const size_t shipped_index = shipped == cands.size() ? all.size() - 1 : shipped;
    out.fit_all = cands[fit(datasets.size())].values;
    for (size_t d = 0; d < datasets.size(); ++d) {
        const size_t c = fit(d);
        FoldResult f;
        f.dataset = datasets[d].name;
        f.fitted = cands[c].values;
        f.in_sample = scores[shipped_index][d];
        f.held_out = scores[c][d];
        f.in_sample_objective = obj[shipped_index][d];
        f.held_out_objective = obj[c][d];
        out.folds.push_back(std::move(f));
    }
    return out;
}

}  // namespace fovea::eval
