# shellcheck shell=bash
# What submit.sh and the batch scripts share: the settings read, the binaries and the config found, the keys made
# once, and a log line's prefix. Sourced, never run; POET_SLURM_DIR names this directory (submit.sh exports it, so
# that a batch script, which SLURM runs from a copy of its own, finds it).
# shellcheck disable=SC2034  # the names are the sourcing script's
set -u
# shellcheck source=settings.sh
. "$POET_SLURM_DIR/settings.sh"

say() { echo "[poet-slurm $(date '+%F %T')] $*" >&2; }
die() {
  say "$*"
  exit 2
}

# A checkout's build or a bundle's bin/.
poet_bin() {
  local name=$1
  case $name in
  poet-coordinator) sub=coordinator ;;
  poet-worker) sub=worker ;;
  *) sub=tools ;;
  esac
  if [ -x "$POET_HOME/bin/$name" ]; then
    echo "$POET_HOME/bin/$name"
  elif [ -x "$POET_BUILD/$sub/$name" ]; then
    echo "$POET_BUILD/$sub/$name"
  else
    die "no $name in $POET_HOME/bin or $POET_BUILD/$sub: set POET_HOME in $POET_SLURM_DIR/settings.sh"
  fi
}

# The config file of POET_PRESET, and the first policy's file (a path, or one of the shipped walkers).
poet_config() {
  case $POET_PRESET in
  */* | *.textproto) echo "$POET_PRESET" ;;
  *) if [ -f "$POET_HOME/configs/$POET_PRESET.textproto" ]; then echo "$POET_HOME/configs/$POET_PRESET.textproto"; else
    echo "$POET_HOME/deploy/configs/$POET_PRESET.textproto"; fi ;;
  esac
}
poet_start_from() {
  [ -n "$POET_START_FROM" ] || return 0
  case $POET_START_FROM in
  /*) echo "$POET_START_FROM" ;;
  *) echo "$POET_HOME/data/$POET_START_FROM" ;;
  esac
}

# The seconds of a SLURM time limit in --time's formats (M, M:S, H:M:S, D-H, D-H:M, D-H:M:S); nothing for no limit
# (INFINITE, UNLIMITED, -1); status 1 for anything else.
poet_time_seconds() {
  local t=$1 d=0 h=0 m=0 s=0
  case $t in
  INFINITE | UNLIMITED | infinite | unlimited | -1) return 0 ;;
  esac
  if [[ $t =~ ^([0-9]+)-([0-9]+)(:([0-9]+)(:([0-9]+))?)?$ ]]; then
    d=${BASH_REMATCH[1]} h=${BASH_REMATCH[2]} m=${BASH_REMATCH[4]:-0} s=${BASH_REMATCH[6]:-0}
  elif [[ $t =~ ^([0-9]+)$ ]]; then
    m=${BASH_REMATCH[1]}
  elif [[ $t =~ ^([0-9]+):([0-9]+)$ ]]; then
    m=${BASH_REMATCH[1]} s=${BASH_REMATCH[2]}
  elif [[ $t =~ ^([0-9]+):([0-9]+):([0-9]+)$ ]]; then
    h=${BASH_REMATCH[1]} m=${BASH_REMATCH[2]} s=${BASH_REMATCH[3]}
  else
    return 1
  fi
  echo $((((10#$d * 24 + 10#$h) * 60 + 10#$m) * 60 + 10#$s))
}

# The CURVE keys, made once: the coordinator's pair and one worker pair, authorised (every worker of the run holds
# it). A lock keeps two jobs starting at once from making two.
poet_keys() {
  { mkdir -p "$POET_KEYS" && chmod 700 "$POET_KEYS"; } || die "cannot make $POET_KEYS"
  (
    flock 9
    if [ ! -s "$POET_KEYS/coordinator.key" ]; then
      "$(poet_bin poetctl)" keygen "$POET_KEYS" coordinator >&2 && "$(poet_bin poetctl)" keygen "$POET_KEYS" worker --authorize >&2
    fi
  ) 9>"$POET_KEYS/.lock" || die "cannot make the CURVE keys in $POET_KEYS"
}

# Waits for the keys another job makes (extra workers may start before the run's first job).
poet_wait_for_keys() {
  local waited=0
  until [ -s "$POET_KEYS/worker.key_secret" ] && [ -s "$POET_KEYS/worker.key" ]; do
    [ $waited -eq 0 ] && say "waiting for the run's keys in $POET_KEYS (made by the run's job when it starts)"
    sleep 5
    waited=$((waited + 5))
  done
}
