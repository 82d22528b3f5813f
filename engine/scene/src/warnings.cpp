#include "dynrt/scene/warnings.h"

#include <algorithm>
#include <atomic>
#include <iostream>
#include <ostream>
#include <set>
#include <string>
#include <tuple>
#include <utility>

namespace dynrt {

namespace {

/// The log warn() collects into, or null: print each warning at once.
std::atomic<WarningLog*> installed{nullptr};

std::string with_source(const Warning& w, const std::string& text) {
    return w.source.empty() ? text : w.source + ": " + text;
}

/// The warnings of one group, in the order they came.
struct Group {
    std::vector<const Warning*> members;
};

/// "a, b, c and 4 more (--verbose lists them)".
std::string list_items(const std::vector<std::string>& items) {
    std::string out;
    const std::size_t shown = std::min(items.size(), WarningLog::kItemsShown);
    for (std::size_t i = 0; i < shown; ++i) {
        if (i > 0) out += i + 1 == items.size() ? " and " : ", ";
        out += items[i];
    }
    if (items.size() > shown) {
        out += " and " + std::to_string(items.size() - shown) + " more (--verbose lists them)";
    }
    return out;
}

std::string group_line(const Group& group) {
    const Warning& first = *group.members.front();
    std::vector<std::string> items;
    std::set<std::string> seen_items, users, details;
    for (const Warning* w : group.members) {
        if (seen_items.insert(w->item).second) items.push_back(w->item);
        if (!w->user.empty()) users.insert(w->user);
        details.insert(w->detail);
    }
    // "N kinds (the shared reason): a, b, c and 4 more, used by U users; effect"; a single
    // item reads "kind: a (reason), used by ...". A reason differing per item is left to
    // --verbose.
    const bool one = items.size() == 1;
    std::string text = one ? first.kind
                           : std::to_string(items.size()) + " " + (first.kinds.empty() ? first.kind : first.kinds);
    if (one && !items.front().empty()) text += ": " + items.front();
    if (details.size() == 1 && !first.detail.empty()) text += " (" + first.detail + ")";
    if (!one) text += ": " + list_items(items);
    if (users.size() == 1) text += ", used by " + *users.begin();
    if (users.size() > 1) text += ", used by " + std::to_string(users.size()) + " " + first.users;
    if (!first.effect.empty()) text += "; " + first.effect;
    return with_source(first, text);
}

}  // namespace

std::string warning_line(const Warning& w) {
    std::string text = w.kind;
    if (!w.item.empty()) text += ": " + w.item;
    if (!w.detail.empty()) text += " (" + w.detail + ")";
    if (!w.user.empty()) text += ", used by " + w.user;
    if (!w.effect.empty()) text += "; " + w.effect;
    return with_source(w, text);
}

void warn(Warning warning) {
    if (WarningLog* log = installed.load()) {
        log->add(std::move(warning));
        return;
    }
    std::cerr << "dynrt: warning: " + warning_line(warning) + "\n" << std::flush;
}

void WarningLog::add(Warning warning) {
    const std::lock_guard lock(mutex_);
    pending_.push_back(std::move(warning));
}

std::size_t WarningLog::pending() const {
    const std::lock_guard lock(mutex_);
    return pending_.size();
}

void WarningLog::print(std::ostream& out, WarningDetail detail) {
    std::vector<Warning> warnings;
    {
        const std::lock_guard lock(mutex_);
        warnings.swap(pending_);
    }
    if (detail == WarningDetail::none) return;
    if (detail == WarningDetail::every) {
        for (const Warning& w : warnings) out << "dynrt: warning: " << warning_line(w) << '\n';
        out << std::flush;
        return;
    }
    // Groups in the order of their first warning.
    std::vector<std::pair<std::tuple<std::string, std::string, std::string>, Group>> groups;
    for (const Warning& w : warnings) {
        const auto key = std::make_tuple(w.source, w.kind, w.effect);
        auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == key; });
        if (it == groups.end()) {
            groups.emplace_back(key, Group{});
            it = groups.end() - 1;
        }
        it->second.members.push_back(&w);
    }
    for (const auto& [key, group] : groups) out << "dynrt: warning: " << group_line(group) << '\n';
    out << std::flush;
}

ScopedWarningLog::ScopedWarningLog(WarningLog& log) : previous_(installed.exchange(&log)) {}

ScopedWarningLog::~ScopedWarningLog() { installed.store(previous_); }

}  // namespace dynrt
