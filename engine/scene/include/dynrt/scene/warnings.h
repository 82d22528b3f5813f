#pragma once
// Warnings: problems dynrt works around rather than fails on (a texture file missing, an
// animation channel it does not play, frames past the end of a clip), told to a person once
// per kind of problem rather than once per material or channel.
//
// Whoever finds such a problem calls warn() with a Warning. By default each warning is printed
// at once as one line on stderr ("dynrt: warning: ..."). A front end that wants them grouped
// (the CLI) installs a WarningLog with ScopedWarningLog: warnings then collect in it, from any
// thread, and print() writes one line per kind of problem with a count and the first few
// items ("city2.aff: 95 texture files cannot be read, used by 390 materials: a.ppm, b.ppm,
// c.ppm and 92 more (--verbose lists them); those materials use their diffuse colour alone").

#include <cstddef>
#include <iosfwd>
#include <mutex>
#include <string>
#include <vector>

namespace dynrt {

/// One problem. Warnings with the same source, kind and effect are one group when printed.
struct Warning {
    // Every member has a default, so that warnings are written with designated initializers
    // naming only what they say ({.kind = ..., .item = ...}).
    /// Where it comes from: the scene file ("city2.aff"), or empty for the command's own flags.
    std::string source{};
    /// The kind of problem, the same words for every warning of its kind, in the singular and
    /// the plural ("texture file cannot be read" / "texture files cannot be read"); `kinds`
    /// empty: the same as `kind`.
    std::string kind{};
    std::string kinds{};
    /// What this warning is about ("corrugated.ppm"): a group counts and lists its distinct
    /// items. Empty for a warning that `kind` says whole.
    std::string item{};
    /// Optional: what uses the item ("material 'fm0'"); a group counts its distinct users,
    /// named in the plural by `users` ("materials").
    std::string user{};
    std::string users{};
    /// Optional: this item's own reason ("Could not open file"), shown when every item of the
    /// group has the same one, and always with --verbose.
    std::string detail{};
    /// Optional: what dynrt does instead ("the diffuse colour is used alone"), once per group.
    std::string effect{};
};

/// How much of the warnings a WarningLog prints.
enum class WarningDetail {
    none,     ///< --quiet: nothing
    grouped,  ///< one line per kind of problem, with counts and the first few items
    every     ///< --verbose: one line per warning, with its user and detail
};

/// Reports `warning`: into the WarningLog installed by a ScopedWarningLog when there is one,
/// else as one line on stderr at once. Thread-safe.
void warn(Warning warning);

/// The one-line form of a single warning, without the "dynrt: warning: " prefix.
std::string warning_line(const Warning& warning);

/// Warnings collected for printing grouped. Thread-safe.
class WarningLog {
public:
    /// How many items a grouped line names before "and N more".
    static constexpr std::size_t kItemsShown = 3;

    void add(Warning warning);
    /// Writes the warnings added since the last print (each line prefixed "dynrt: warning: ")
    /// at `detail`, in the order their groups first appeared, and forgets them.
    void print(std::ostream& out, WarningDetail detail);
    /// Warnings added and not yet printed.
    std::size_t pending() const;

private:
    mutable std::mutex mutex_;
    std::vector<Warning> pending_;
};

/// Installs `log` as where warn() sends warnings, for this object's lifetime (process-wide:
/// warnings from every thread go there). Scopes nest; the innermost wins.
class ScopedWarningLog {
public:
    explicit ScopedWarningLog(WarningLog& log);
    ~ScopedWarningLog();
    ScopedWarningLog(const ScopedWarningLog&) = delete;
    ScopedWarningLog& operator=(const ScopedWarningLog&) = delete;

private:
    WarningLog* previous_;
};

}  // namespace dynrt
