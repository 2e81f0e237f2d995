#include "fovea/eval/scoring.hpp"

#include <algorithm>
#include <cmath>

namespace fovea::eval {

using gaze::Event;

const char* event_name(Event e) {
    switch (e) {
        case Event::kFixation: return "fixation";
        case Event::kSaccade: return "saccade";
        case Event::kPso: return "pso";
        case Event::kPursuit: return "pursuit";
        case Event::kBlink: return "blink";
        default: return "undefined";
    }
}

void Agreement::add(bool a, bool b) {
    if (a && b) {
        both += 1;
    } else if (a) {
        only_a += 1;
    } else if (b) {
        only_b += 1;
    } else {
        neither += 1;
    }
}

void Agreement::add(const Agreement& o) {
    both += o.both;
    only_a += o.only_a;
    only_b += o.only_b;
    neither += o.neither;
}

double Agreement::kappa() const {
    const double n = both + only_a + only_b + neither;
    if (n <= 0) return gaze::kNaN;
    const double po = (both + neither) / n;
    const double pa = (both + only_a) / n, pb = (both + only_b) / n;
    const double pe = pa * pb + (1 - pa) * (1 - pb);
    if (pe >= 1.0) return gaze::kNaN;
    return (po - pe) / (1 - pe);
}

double Agreement::f1() const {
    const double d = 2 * both + only_a + only_b;
    return d > 0 ? 2 * both / d : gaze::kNaN;
}

void EventCounts::add(const EventCounts& o) {
    hits += o.hits;
    detected += o.detected;
    labelled += o.labelled;
}

double EventCounts::f1() const {
    const double d = detected + labelled;
    return d > 0 ? 2 * hits / d : gaze::kNaN;
}

namespace {

struct Run {
    size_t begin, end;  // [begin, end)
};

std::vector<Run> runs(std::span<const Event> s, Event e) {
    std::vector<Run> out;
    for (size_t i = 0; i < s.size();) {
        if (s[i] != e) {
            ++i;
            continue;
        }
        size_t j = i;
        while (j < s.size() && s[j] == e) ++j;
        out.push_back({i, j});
        i = j;
    }
    return out;
}

}  // namespace

void count_events(std::span<const Event> detected, std::span<const Event> labelled, Event e,
                  EventCounts& out, double min_iou) {
    const size_t n = std::min(detected.size(), labelled.size());
    const auto det = runs(detected.first(n), e);
    const auto lab = runs(labelled.first(n), e);
    std::vector<bool> matched(lab.size(), false);
    size_t first = 0;  // coder events ending before the current detection never overlap again
    double hits = 0;
    for (const Run& d : det) {
        while (first < lab.size() && lab[first].end <= d.begin) ++first;
        for (size_t k = first; k < lab.size() && lab[k].begin < d.end; ++k) {
            if (matched[k]) continue;
            const double inter =
                static_cast<double>(std::min(d.end, lab[k].end) - std::max(d.begin, lab[k].begin));
            const double uni =
                static_cast<double>(std::max(d.end, lab[k].end) - std::min(d.begin, lab[k].begin));
            if (inter / uni >= min_iou) {
                matched[k] = true;
                hits += 1;
                break;
            }
        }
    }
    out.hits += hits;
    out.detected += static_cast<double>(det.size());
    out.labelled += static_cast<double>(lab.size());
}

std::vector<Event> fold_to_scheme(std::span<const Event> detected, const Dataset& dataset) {
    const bool pso = dataset.labels(Event::kPso), pursuit = dataset.labels(Event::kPursuit);
    const bool blink = dataset.labels(Event::kBlink);
    std::vector<Event> out(detected.begin(), detected.end());
    for (Event& e : out) {
        if (e == Event::kPso && !pso) e = dataset.pso_without_label;
        if (e == Event::kPursuit && !pursuit) e = Event::kFixation;
        if (e == Event::kBlink && !blink) e = Event::kUnknown;
        if (!dataset.labels(e)) e = Event::kUnknown;
    }
    return out;
}

std::vector<Event> coder_labels(std::span<const Event> labels, const Dataset& dataset) {
    std::vector<Event> out(labels.begin(), labels.end());
    for (Event& e : out)
        if (!dataset.labels(e)) e = Event::kUnknown;
    return out;
}

DatasetScore score(const Dataset& dataset, const std::vector<std::vector<Event>>& detections) {
    DatasetScore result;
    for (size_t r = 0; r < dataset.recordings.size() && r < detections.size(); ++r) {
        const Recording& rec = dataset.recordings[r];
        const std::vector<Event> det = fold_to_scheme(detections[r], dataset);
        const size_t n = std::min(det.size(), rec.samples.size());
        result.samples += n;
        for (const auto& [coder, raw_labels] : rec.coders) {
            const std::vector<Event> lab = coder_labels(raw_labels, dataset);
            const size_t m = std::min(n, lab.size());
            for (Event e : dataset.scheme) {
                Cell& c = result.cells[rec.stimulus][event_name(e)][coder];
                for (size_t i = 0; i < m; ++i) c.samples.add(det[i] == e, lab[i] == e);
                count_events(std::span(det).first(m), std::span(lab).first(m), e, c.events);
            }
        }
    }
    for (auto& [stimulus, events] : result.cells) {
        for (auto& [event, coders] : events) {
            Cell all;
            for (const auto& [coder, c] : coders) {
                all.samples.add(c.samples);
                all.events.add(c.events);
            }
            coders[kAllCoders] = all;
        }
    }
    return result;
}

void Spread::add(double v) {
    if (!std::isfinite(v)) return;
    mean = pairs ? (mean * pairs + v) / (pairs + 1) : v;
    min = pairs ? std::min(min, v) : v;
    max = pairs ? std::max(max, v) : v;
    ++pairs;
}

CoderTable coder_agreement(const Dataset& dataset) {
    // cells[stimulus][event][(coder a, coder b)]
    std::map<std::string, std::map<Event, std::map<std::pair<std::string, std::string>, Cell>>>
        pairs;
    for (const Recording& rec : dataset.recordings) {
        for (auto a = rec.coders.begin(); a != rec.coders.end(); ++a) {
            const std::vector<Event> la = coder_labels(a->second, dataset);
            for (auto b = std::next(a); b != rec.coders.end(); ++b) {
                const std::vector<Event> lb = coder_labels(b->second, dataset);
                const size_t m = std::min(la.size(), lb.size());
                for (Event e : dataset.scheme) {
                    Cell& c = pairs[rec.stimulus][e][{a->first, b->first}];
                    for (size_t i = 0; i < m; ++i) c.samples.add(la[i] == e, lb[i] == e);
                    count_events(std::span(la).first(m), std::span(lb).first(m), e, c.events);
                }
            }
        }
    }
    CoderTable out;
    for (const auto& [stimulus, events] : pairs) {
        for (const auto& [event, per_pair] : events) {
            CoderAgreement& agg = out[stimulus][event_name(event)];
            for (const auto& [pair, c] : per_pair) {
                agg.kappa.add(c.kappa());
                agg.f1_sample.add(c.f1_sample());
                agg.f1_event.add(c.f1_event());
            }
        }
    }
    return out;
}

}  // namespace fovea::eval
