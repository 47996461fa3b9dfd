#pragma once
// CPU time of the whole process (user + system, every thread), the figure a
// benchmark on a shared machine reports beside wall time: other processes'
// load stretches wall time but not this.

namespace plumage {

// Seconds of user + system CPU time this process has used so far (getrusage).
double process_cpu_seconds();

}  // namespace plumage
