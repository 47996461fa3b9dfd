#!/usr/bin/env bash
# Renders one image as N parts on whatever runs them, then merges the parts into
# the image a single run gives, bit for bit (docs/rendering.md, "Split renders").
#
#   scripts/split_render.sh N OUT -- INPUT [plumage render options...]
#
# RUNNER picks what runs the N `plumage render INPUT --tile I/N -o PART_I.exr`:
#   local     (default) N at a time here (xargs -P JOBS, JOBS default: nproc)
#   parallel  GNU parallel; SSHLOGIN="host1,host2" sends the parts over ssh
#             (`parallel --sshlogin`): every host needs the same plumage (PLUMAGE)
#             and the same paths, e.g. a shared file system.
#   slurm     a Slurm job array of N tasks (sbatch --array=1-N --wait); the parts
#             land on the shared folder PARTS; SBATCH_ARGS adds options
#             (partition, time, cpus-per-task).
# PARTS (default OUT.parts/) holds the parts; they are kept, so a failed part can
# be rerun alone. PLUMAGE is the binary (default: build/plumage, made absolute).
set -euo pipefail
usage() { echo "usage: [RUNNER=local|parallel|slurm] $0 N OUT -- INPUT [render options]" >&2; exit 2; }
[[ $# -ge 4 && $3 == "--" ]] || usage
n=$1 out=$2
shift 3
[[ $n =~ ^[0-9]+$ && $n -ge 1 ]] || usage
plumage=$(realpath "${PLUMAGE:-$(dirname "$0")/../build/plumage}")
runner=${RUNNER:-local}
parts=$(realpath -m "${PARTS:-$out.parts}")
mkdir -p "$parts"
render_args=("$@")
quoted=$(printf "%q " "${render_args[@]}")
part() { printf "%s/part_%0${#n}d.exr" "$parts" "$1"; }

case $runner in
  local)
    seq 1 "$n" | xargs -P "${JOBS:-$(nproc)}" -I{} sh -c \
      "\"$plumage\" -q render $quoted --threads 1 --tile {}/$n -o \"\$(printf '%s/part_%0${#n}d.exr' '$parts' {})\""
    ;;
  parallel)
    command -v parallel >/dev/null || { echo "$0: GNU parallel is not installed (apt install parallel)" >&2; exit 1; }
    ssh_args=()
    [[ -n ${SSHLOGIN:-} ]] && ssh_args=(--sshlogin "$SSHLOGIN")
    parallel --halt now,fail=1 "${ssh_args[@]}" \
      "\"$plumage\" -q render $quoted --tile {}/$n -o $parts/part_{=\$_=sprintf('%0${#n}d',\$_)=}.exr" ::: $(seq 1 "$n")
    ;;
  slurm)
    command -v sbatch >/dev/null || { echo "$0: sbatch not found: run this on a Slurm submit host" >&2; exit 1; }
    job="$parts/job.sh"
    {
      echo "#!/usr/bin/env bash"
      echo "#SBATCH --job-name=plumage-parts"
      echo "#SBATCH --array=1-$n"
      echo "#SBATCH --output=$parts/slurm_%A_%a.log"
      echo "set -euo pipefail"
      echo "i=\$SLURM_ARRAY_TASK_ID"
      echo "\"$plumage\" -q render $quoted --tile \$i/$n -o \"\$(printf '%s/part_%0${#n}d.exr' '$parts' \"\$i\")\""
    } >"$job"
    # shellcheck disable=SC2086
    sbatch --wait ${SBATCH_ARGS:-} "$job"
    ;;
  *) usage ;;
esac

mapfile -t files < <(for ((i = 1; i <= n; ++i)); do part "$i"; echo; done)
"$plumage" -q merge "${files[@]}" -o "$out"
echo "wrote $out from $n parts in $parts/ ($runner)"
