#!/usr/bin/env bash
# Validates the Kubernetes manifests offline, in strict mode (unknown fields are errors),
# against the schemas of every Kubernetes version the README names (1.29 to 1.37), with
# kubernetes-validate from PyPI (it bundles the schemas) in a throwaway virtual environment.
set -euo pipefail
cd "$(dirname "$0")"
venv=$(mktemp -d)
trap 'rm -rf "$venv"' EXIT
# (Debian's own python3 needs python3-venv for this; install it where it is missing.)
python3 -m venv "$venv" 2>/dev/null || {
    apt-get install -y -qq python3-venv >/dev/null
    python3 -m venv "$venv"
}
"$venv/bin/pip" install --quiet --disable-pip-version-check "kubernetes-validate==1.37.0"
for v in 1.29.0 1.30.0 1.31.0 1.32.0 1.33.0 1.34.0 1.35.0 1.36.0 1.37.0; do
    "$venv/bin/kubernetes-validate" --strict --kubernetes-version "$v" --quiet study-job.yaml merge-job.yaml fetch-pod.yaml design-job.yaml design-merge-job.yaml
    echo "Kubernetes $v: study-job.yaml, merge-job.yaml, fetch-pod.yaml, design-job.yaml, design-merge-job.yaml valid (strict)"
done
