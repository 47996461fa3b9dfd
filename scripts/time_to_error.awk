# CPU time to a target RMSE from a ladder CSV (a header row naming the columns),
# per group: log RMSE against log cpu_seconds interpolated between the two rungs
# around the target. Used by speed_at_error.sh and speed_vs_pbrt.sh.
#   awk -F, -v target=0.01 -v by=mode -f scripts/time_to_error.awk ladder.csv
# Prints "GROUP: RMSE T at S CPU s" per group, or that the ladder does not bracket T;
# with -v compare=1 and two groups that reach T, also how many times faster the
# second group (in file order) is than the first ("B faster than A by Rx").
NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
{
  g = $col[by]
  if (!(g in n)) order[++groups] = g
  n[g]++
  c[g, n[g]] = $col["cpu_seconds"]
  e[g, n[g]] = $col["rmse"]
  s[g, n[g]] = ("spp" in col) ? $col["spp"] : 0
}
END {
  for (k = 1; k <= groups; ++k) {
    g = order[k]
    for (r = 1; r < n[g]; ++r)
      if (e[g, r] >= target && e[g, r + 1] <= target) {
        f = (log(target) - log(e[g, r])) / (log(e[g, r + 1]) - log(e[g, r]))
        at[g] = exp(log(c[g, r]) + f * (log(c[g, r + 1]) - log(c[g, r])))
        spp = exp(log(s[g, r]) + f * (log(s[g, r + 1]) - log(s[g, r])))
        printf "%s: RMSE %g at %.3f CPU s (%.0f spp)\n", g, target, at[g], spp
        break
      }
    if (!(g in at)) printf "%s: RMSE %g not bracketed by the ladder\n", g, target
  }
  if (compare && groups == 2 && (order[1] in at) && (order[2] in at))
    printf "%s faster than %s by %.2fx\n", order[2], order[1], at[order[1]] / at[order[2]]
}
