# Sourced by controls.sh and figure3.sh, which take the same arguments: BUILD_DIR RUN_DIR PAIR OUT_DIR
# [coordinator flags...]. Reads them into build, run, pair and out (the flags stay in "$@"), checks the tools
# (coordinator, lineage and the one named in $third_tool, e.g. poet-report), makes OUT_DIR and sets root, walker
# (the shipped flat walker) and budget (the ES steps of the pair's POET lineage, from poet-lineage). The caller
# sets $usage first.
build=${1:?$usage}
run=${2:?$usage}
pair=${3:?$usage}
out=${4:?$usage}
shift 4
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
coordinator=$build/coordinator/poet-coordinator
lineage=$build/tools/poet-lineage
for tool in "$coordinator" "$lineage" "$build/tools/$third_tool"; do
  [[ -x $tool ]] || { echo "no $tool: build first" >&2; exit 2; }
done
[[ $pair =~ ^[0-9]+$ ]] || { echo "PAIR must be a pair id (a non-negative integer), got '$pair'" >&2; exit 2; }
walker=$root/data/walkers/flat-walker.json
mkdir -p "$out"
budget=$("$lineage" --run-dir "$run" --pair "$pair" | sed -n 's/^direct-path budget: \([0-9]*\) ES steps$/\1/p')
[[ -n $budget ]] || { echo "poet-lineage gave no budget for pair $pair of $run" >&2; exit 1; }
