#!/usr/bin/python3
"""Runs every SOFA example scene of a folder through `penalty info` and `penalty run`, and writes the
coverage table docs/sofa-examples.md (issue 15).

For each `*.scn` below the folder (default ../shared/sofa/examples, relative to the repository root):
  - builds: `penalty info SCENE --data-dir ...` exits 0;
  - runs:   `penalty run SCENE --steps 100 --data-dir ...` exits 0 (exit 0 means finite states: a
            NaN/inf or a diverging DOF is exit 3), with its steps/s and contacts per step (mean, max);
  - matches SOFA: where SOFA's states after init and after 100 steps exist
            (<folder>/../examples-states/<scene path without .scn>/<k>_<name>_mstate.txt.gz), the run is
            repeated for 101 steps (penalty exports the state at the start of each step) with
            `--compare-trajectory` and SOFA's criterion (mean over the states of sum_T sum_i |dx_i| / DOFs
            <= 1e-4) decides; with --sofa-head EXE, a scene without shared states gets SOFA HEAD's, made by
            `EXE SCENE 100 DIR` into --made-states (default build/sofa-head-states, kept from run to run),
            unless SOFA HEAD fails to load it (a component not created, a node's init failed, a missing
            file: the table says so; a component both drop, an old name SOFA HEAD no longer knows at
            all, is no failure: SOFA HEAD's states are then the scene's SOFA trajectory);
  - first blocker: the component named by the first error (an unknown component, or the component
            whose attribute or build failed).
Data files are looked for in the scene's folder, then <folder>/.. (which holds mesh/) and <folder>
(which holds Objects/, SOFA's included files: SOFA's data path holds both share/ and examples/).

The table ends with the components SOFA's Python example scripts create (`addObject('Type', ...)` in
the *.py files below each --py-examples folder; default ../sp3-src/examples and ../sofa-src/examples,
relative to the repository root, where they exist) and what penalty's registry (`penalty info
--components`) does with each: built, accepted and ignored, refused, or unknown.

usage: scripts/sofa-examples.py [FOLDER] [--penalty EXE] [--out FILE.md] [--timeout S] [--jobs J]
                                [--check] [--expected FILE] [--write-expected] [--py-examples DIR]...
  --check            exit 1 naming every scene of the expected list (tests/sofa_examples_expected.txt)
                     that no longer runs; the table is written only with --out
  --write-expected   rewrite the expected list with the scenes that run now
  --sofa-head EXE    make SOFA HEAD's states of the scenes without shared ones (../shared/sofa-head/sofa-head)
"""
import argparse
import collections
import concurrent.futures
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
STEPS = 100
SOFA_CRITERION = 1e-4  # SOFA's regression test: mean absolute error per DOF over the run


def rel(path):
    return os.path.relpath(path, REPO)


def penalty_error(stderr):
    """The text after 'penalty: error: ' of the last such line (or the last line of stderr), its
    paths relative to the checkout (the commands get absolute ones: they run in folders of their own)."""
    stderr = stderr.replace(os.path.dirname(REPO) + os.sep, '..' + os.sep)
    lines = [l for l in stderr.splitlines() if l.strip()]
    for line in reversed(lines):
        if line.startswith('penalty: error: '):
            return line[len('penalty: error: '):]
    return lines[-1] if lines else ''


def blocker_of(message):
    """(component, reason) from an error message `file:line: unknown component 'X' ...` or
    `file:line: Type 'name': ...` (the file part may be an included file)."""
    text = re.sub(r'^.*?\.(scn|xml|py):\d+: ', '', message, count=1)
    m = re.match(r"unknown component '([^']+)'", text)
    if m:
        return m.group(1), 'unknown component'
    m = re.match(r'([A-Za-z_][A-Za-z0-9_<>,]*)', text)
    reason = re.sub(r'\s*\(included from .*\)$', '', text)
    return (m.group(1) if m else '?'), reason


def component_types(scene, search_dirs, depth=0):
    """The component types a scene file uses, its <include>d files' too (SOFA's XML syntax:
    every element but <Node> is a component; <Object type="T"/> is T; `include` counts as one).
    Read with regular expressions, as tinyxml2 accepts files Python's XML parser refuses."""
    try:
        with open(scene, errors='replace') as f:
            text = re.sub(r'<!--.*?-->', '', f.read(), flags=re.DOTALL)
    except OSError:
        return set()
    types = set()
    for m in re.finditer(r'<([A-Za-z_][A-Za-z0-9_]*)((?:[^>"\']|"[^"]*"|\'[^\']*\')*)>', text):
        tag, attributes = m.group(1), m.group(2)
        if tag == 'Node':
            continue
        if tag == 'Object':
            t = re.search(r'\btype\s*=\s*["\']([^"\']*)', attributes)
            tag = t.group(1) if t else ''
        elif tag == 'include':
            h = re.search(r'\bhref\s*=\s*["\']([^"\']*)', attributes)
            href = h.group(1) if h else ''
            for d in [os.path.dirname(scene)] + search_dirs:
                f = os.path.join(d, href)
                if href and os.path.isfile(f) and depth < 16:
                    types |= component_types(f, search_dirs, depth + 1)
                    break
        types.add(tag)
    types.discard('')
    return types


def run(cmd, timeout):
    """Runs `cmd` in a folder of its own, removed after: a scene's exporters write relative to it
    (MeshExporter, VisualModelOBJExporter in Hexa2TetraTopologicalMapping_export.scn), never into
    the checkout nor into another scene's folder."""
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix='sofa-examples-') as folder:
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=folder)
            return r.returncode, r.stdout, r.stderr, time.monotonic() - start
        except subprocess.TimeoutExpired:
            return None, '', '', timeout


# What in SOFA HEAD's log means its states are not the scene's: a component it did not create, a
# node whose init failed, a file it did not find (SOFA then runs what is left).
NOT_CREATED = (re.compile(r'Object type (\S+?)<\S*> was not created'), 'SOFA HEAD does not create {}')
NODE_INIT_FAILED = (re.compile(r'Node initialization failed'), 'a node of SOFA HEAD failed its init')
FILE_NOT_FOUND = (re.compile(r"File: '([^']+)' not found"), 'SOFA HEAD does not find {}')
SOFA_LOAD_FAILURES = [NOT_CREATED, NODE_INIT_FAILED, FILE_NOT_FOUND]
# penalty's registry's summary of the old names SOFA HEAD no longer knows at all (no class, no
# rename: src/scene/components.cpp, kAbsentFromSofa): SOFA HEAD creates nothing for them, its
# loader says a node's init failed, and it runs the scene without them, as penalty does. Such a
# scene's SOFA HEAD states are its SOFA trajectory when those are the only components not created.
UNKNOWN_TO_SOFA = 'unknown to SOFA today'


def sofa_load_failure(args, log):
    """Why SOFA HEAD's states of a scene whose run logged `log` are not the scene's, or None."""
    not_created = set(NOT_CREATED[0].findall(log))
    failures = SOFA_LOAD_FAILURES
    if not_created and all(UNKNOWN_TO_SOFA in args.components.get(t, ('', ''))[1] for t in not_created):
        failures = [FILE_NOT_FOUND]  # the node's failed init is theirs: both run the scene without them
    for pattern, text in failures:
        m = pattern.search(log)
        if m:
            return text.format(*m.groups())
    return None


def made_states(args, scene, name):
    """SOFA HEAD's states after init and STEPS steps of `scene` (made once into --made-states):
    (folder, None), or (None, why there are none)."""
    target = os.path.join(args.made_states, os.path.splitext(name)[0])
    refused = target + '.refused'
    if os.path.isfile(refused):
        with open(refused) as f:
            return None, f.read().strip()
    if not os.path.isdir(target):
        os.makedirs(os.path.dirname(target), exist_ok=True)
        partial = target + '.partial'
        shutil.rmtree(partial, ignore_errors=True)
        code, out, err, _ = run([args.sofa_head, scene, str(STEPS), partial], 10 * args.timeout)
        why = sofa_load_failure(args, out + err)
        if why is None and code != 0:
            why = 'SOFA HEAD ' + ('took too long' if code is None else f'exits {code}')
        if why is None and not glob.glob(os.path.join(partial, '*_mstate.txt')):
            why = 'SOFA HEAD writes no state (no solver)'
        if why is not None:
            shutil.rmtree(partial, ignore_errors=True)
            with open(refused, 'w') as f:
                f.write(why + '\n')
            return None, why
        os.rename(partial, target)
    return target, None


def check_scene(args, scene):
    name = os.path.relpath(scene, args.folder)
    data = []
    for d in args.data_dirs:
        data += ['--data-dir', d]
    row = {'scene': name, 'builds': False, 'runs': False, 'steps_per_s': None, 'contacts': None,
           'sofa': 'no reference', 'has_states': False, 'blocker': '', 'reason': '', 'uses': component_types(scene, args.data_dirs)}

    states = os.path.join(args.states, os.path.splitext(name)[0])
    if not os.path.isdir(states) and args.sofa_head:
        states, refusal = made_states(args, scene, name)
        if refusal:
            row['sofa'] = f'no reference ({refusal})'
    if states and os.path.isdir(states):
        row['has_states'], row['sofa'] = True, 'no (does not run)'

    code, out, err, _ = run([args.penalty, 'info', scene] + data, args.timeout)
    if code is None:
        row['blocker'], row['reason'] = '(timeout)', f'penalty info took more than {args.timeout:g} s'
        return row
    if code != 0:
        row['blocker'], row['reason'] = blocker_of(penalty_error(err))
        return row
    row['builds'] = True

    code, out, err, _ = run([args.penalty, 'run', scene, '--steps', str(STEPS), '--quiet', '--threads', '1'] + data,
                            args.timeout)
    if code is None:
        row['blocker'], row['reason'] = '(timeout)', f'{STEPS} steps took more than {args.timeout:g} s'
        return row
    # exit 3: penalty's divergence check stopped the run (beyond SOFA); SOFA's trajectory is still
    # compared, with the check off, since SOFA runs such a scene on
    diverged = code == 3
    if code != 0:
        message = penalty_error(err)
        row['blocker'] = {3: '(diverged)'}.get(code, f'(exit {code})')
        row['reason'] = re.sub(r'\s*\(included from .*\)$', '', re.sub(r'^.*?\.(scn|xml):\d+: ', '', message))
        if not diverged:
            return row
    else:
        row['runs'] = True
        m = re.search(r'([0-9.eE+-]+) steps/s', out)
        row['steps_per_s'] = float(m.group(1)) if m else None
        m = re.search(r'contacts per step: mean ([0-9.eE+-]+), max (\d+)', out)
        row['contacts'] = (float(m.group(1)), int(m.group(2))) if m else None

    if row['has_states']:
        with tempfile.TemporaryDirectory() as tmp:
            code, out, err, _ = run([args.penalty, 'run', scene, '--steps', str(STEPS + 1), '--quiet', '--threads', '1',
                                     '--export-states', tmp, '--export-every', str(STEPS),
                                     '--compare-trajectory', states, '--trajectory-threshold', '1e300'] +
                                    (['--divergence-factor', '0'] if diverged else []) + data,
                                    args.timeout)
        m = re.search(r"SOFA's criterion ([^ ]+)", out)
        criterion = m.group(1) if m else None
        try:
            criterion = f'{float(criterion):.3g}'
        except (TypeError, ValueError):
            pass
        if code == 0:
            row['sofa'] = f'yes ({criterion})'
        elif code is None:
            row['sofa'] = 'no (timeout)'
        elif criterion is not None and criterion not in ('inf',):
            row['sofa'] = f'no ({criterion})'
        else:
            problem = re.search(r'(problem|trajectory): (.*)', out)
            row['sofa'] = 'no (' + (problem.group(2)[:80] if problem else penalty_error(err)[:80]) + ')'
    return row


def unknown_components(args, types):
    """The component types `penalty info` refuses as unknown, probed one at a time on a scene
    holding only that component (any other error means penalty knows the type)."""
    def probe(t):
        with tempfile.NamedTemporaryFile('w', suffix='.scn', delete=False) as f:
            f.write(f'<Node name="root"><{t}/></Node>\n')
        try:
            code, _, err, _ = run([args.penalty, 'info', f.name], args.timeout)
        finally:
            os.unlink(f.name)
        return code is not None and code != 0 and f"unknown component '{t}'" in err
    valid = sorted(t for t in types if re.fullmatch(r'[A-Za-z_][A-Za-z0-9_]*', t))
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        return {t for t, unknown in zip(valid, pool.map(probe, valid)) if unknown}


def short_reason(component, reason):
    """'unknown', "attribute 'method'", or the message without the component's name (60 chars)."""
    if reason == 'unknown component':
        return 'unknown'
    m = re.search(r"attribute '([^']+)'", reason)
    if m:
        return f"attribute '{m.group(1)}'"
    text = re.sub(r"^" + re.escape(component) + r"( '[^']*')?: ", '', reason)
    return text[:60] + ('...' if len(text) > 60 else '')


def cell(text):
    return str(text).replace('|', '\\|').replace('\n', ' ')


def registry(args):
    """{type: (section, summary)} from `penalty info --components` (the component registry)."""
    code, out, _, _ = run([args.penalty, 'info', '--components'], args.timeout)
    types, section = {}, ''
    for line in (out or '').splitlines() if code == 0 else []:
        m = re.fullmatch(r'(\S.*):', line)
        if m:
            section = m.group(1)
            continue
        m = re.fullmatch(r'  ([A-Za-z_][A-Za-z0-9_]*): (.*)', line)
        if m:
            types[m.group(1)] = (section, m.group(2))
    return types


def python_example_components(folders):
    """{type: set of scripts} for every `addObject('Type'` / `createObject('Type'` in the *.py files."""
    uses = collections.defaultdict(set)
    pattern = re.compile(r"""(?:addObject|createObject)\(\s*['"]([A-Za-z_][A-Za-z0-9_]*)['"]""")
    for folder in folders:
        for d, _, files in os.walk(folder):
            for f in sorted(files):
                if not f.endswith('.py'):
                    continue
                path = os.path.join(d, f)
                try:
                    with open(path, errors='replace') as fh:
                        text = fh.read()
                except OSError:
                    continue
                name = os.path.relpath(path, os.path.dirname(os.path.normpath(folder)))
                for t in pattern.findall(text):
                    uses[t].add(name)
    return uses


def python_section(args):
    """The section on SOFA's Python example scripts: their component types and penalty's registry."""
    folders = [os.path.normpath(f) for f in args.py_examples if os.path.isdir(f)]
    uses = python_example_components(folders)
    if not uses:
        return []
    known = args.components

    def status(t):
        if t not in known:
            return 'no'
        section, summary = known[t]
        if 'ignored' in section:
            return 'ignored (' + section.replace(' (ignored)', '') + ')'
        if 'refused' in summary:
            return 'refused (' + summary + ')'
        return 'yes (' + section + ')'
    scripts = collections.defaultdict(set)
    for t, files in uses.items():
        for f in files:
            scripts[f].add(t)
    usable = sum(1 for ts in scripts.values() if all(status(t) != 'no' and not status(t).startswith('refused') for t in ts))
    n_known = sum(1 for t in uses if status(t) != 'no')
    lines = ['', "## Components of SOFA's Python example scripts", '',
             "The component types created by `addObject('Type', ...)` in the example scripts of " +
             ', '.join(f'`{os.path.relpath(f, REPO)}`' for f in folders) + f' ({len(scripts)} scripts, {len(uses)} types), and what',
             "penalty's component registry (`penalty info --components`) does with each: *yes* (built; the registry",
             'section in parentheses), *ignored* (accepted, changes no number), *refused*, or *no* (unknown).',
             f'penalty knows {n_known} of the {len(uses)} types; {usable} of the {len(scripts)} scripts create no',
             'unknown or refused type (a script also needs SofaPython3 itself, which penalty does not run).', '',
             '| component | scripts using it | penalty |', '| --- | ---: | --- |']
    for t in sorted(uses, key=lambda t: (-len(uses[t]), t)):
        lines.append(f'| `{cell(t)}` | {len(uses[t])} | {cell(status(t))} |')
    return lines


def write_table(args, rows, unknown, out):
    total = len(rows)
    builds = sum(r['builds'] for r in rows)
    runs = sum(r['runs'] for r in rows)
    with_states = [r for r in rows if r['has_states']]
    matches = sum(r['sofa'].startswith('yes') for r in rows)
    first = collections.Counter(r['blocker'] for r in rows if r['blocker'] and not r['blocker'].startswith('('))
    uses = collections.Counter(t for r in rows for t in r['uses'])
    lines = [
        '# SOFA\'s penalty-contact example scenes',
        '',
        'Generated by `scripts/sofa-examples.py` (issue 15) from the scenes of `../shared/sofa/examples/` (SOFA\'s own',
        'files, never committed): each goes through `penalty info` and `penalty run --steps 100` with',
        '`--data-dir ../shared/sofa --data-dir ../shared/sofa/examples`. *Runs* means exit 0 (finite states);',
        '*matches SOFA* compares the states after init and after 100 steps with SOFA HEAD\'s',
        '(`../shared/sofa/examples-states/`, about half of the scenes' + (
            '; the others\' made by running SOFA HEAD, `--sofa-head ../shared/sofa-head/sofa-head`, where it loads'
            ' them' if args.sofa_head else '') + ') under SOFA\'s criterion (mean absolute',
        'error per DOF summed over the compared steps, averaged over the states, ≤ 1e-4; the figure is in',
        'parentheses). *First blocker* is the component named by the first error. Steps/s are wall-clock on',
        'the machine that ran the script (one thread, two scenes at a time). Regenerate with',
        '`scripts/sofa-examples.py` (`--write-expected` also rewrites `tests/sofa_examples_expected.txt`, the',
        'scenes CI\'s `scripts/sofa-examples.py --check` requires to run).',
        '',
        f'**builds {builds} / runs {runs} of {total}**; matches SOFA {matches} of the {len(with_states)} scenes with '
        f'SOFA states ({sum(r["runs"] for r in with_states)} of them run).',
        '',
        '## Blocking components',
        '',
        'Ranked by the number of scenes whose first error names the component; *scenes using it* counts every',
        'scene (of all ' + str(total) + ') that has the component, its included files counted.',
        '',
        '| component | first blocker of | scenes using it | why (scenes) |',
        '| --- | ---: | ---: | --- |',
    ]
    why = collections.defaultdict(collections.Counter)
    for r in rows:
        if r['blocker'] and not r['blocker'].startswith('('):
            why[r['blocker']][short_reason(r['blocker'], r['reason'])] += 1
    for comp, n in sorted(first.items(), key=lambda kv: (-kv[1], -uses[kv[0]], kv[0])):
        reasons = '; '.join(f'{cell(k)} ({v})' for k, v in why[comp].most_common())
        lines.append(f'| `{cell(comp)}` | {n} | {uses[comp]} | {reasons} |')
    missing = {r['scene']: r['uses'] & unknown for r in rows}
    complete = sum(1 for m in missing.values() if not m)
    alone = collections.Counter(next(iter(m)) for m in missing.values() if len(m) == 1)
    lines += ['', '## Components penalty does not know', '',
              f'{complete} of the {total} scenes have no component `penalty info` refuses as unknown (probed one type at a',
              'time; a known component can still stop a scene on an attribute or a case it does not handle). Per unknown',
              'component: the scenes using it, and the scenes where it is the only unknown component (adding it alone',
              'removes their last unknown component).', '',
              '| component | scenes using it | only unknown in |', '| --- | ---: | ---: |']
    for comp in sorted(unknown, key=lambda c: (-uses[c], -alone[c], c)):
        lines.append(f'| `{cell(comp)}` | {uses[comp]} | {alone[comp]} |')
    other = collections.Counter(r['blocker'] for r in rows if r['blocker'].startswith('('))
    if other:
        lines += ['', 'Scenes that build but stop while running: ' +
                  ', '.join(f'{k} {v}' for k, v in sorted(other.items())) + '.']
    lines += ['', '## Scenes', '',
              '| scene | builds | runs | steps/s | contacts per step (mean, max) | matches SOFA | first blocker |',
              '| --- | --- | --- | ---: | --- | --- | --- |']
    for r in rows:
        sps = f'{r["steps_per_s"]:.4g}' if r['steps_per_s'] is not None else ''
        con = f'{r["contacts"][0]:g}, {r["contacts"][1]}' if r['contacts'] else ''
        blocker = ''
        if r['blocker']:
            blocker = f'`{cell(r["blocker"])}`' if not r['blocker'].startswith('(') else cell(r['blocker'])
            if r['reason'] and r['reason'] != 'unknown component':
                blocker += ': ' + cell(r['reason'][:160])
        lines.append(f'| {cell(r["scene"])} | {"yes" if r["builds"] else "no"} | {"yes" if r["runs"] else "no"} | '
                     f'{sps} | {con} | {cell(r["sofa"])} | {blocker} |')
    lines += python_section(args)
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument('folder', nargs='?', default=os.path.join(REPO, '..', 'shared', 'sofa', 'examples'))
    p.add_argument('--penalty', default=os.path.join(REPO, 'build', 'release', 'bin', 'penalty'))
    p.add_argument('--data-dir', dest='data_dirs', action='append', default=None,
                   help='folders searched for data and included files (default: FOLDER/.. and FOLDER)')
    p.add_argument('--states', default=None, help="SOFA's states (default: FOLDER/../examples-states)")
    p.add_argument('--sofa-head', default=None,
                   help="SOFA HEAD's sofa-head: make the states of the scenes without shared ones")
    p.add_argument('--made-states', default=os.path.join(REPO, 'build', 'sofa-head-states'),
                   help='where --sofa-head keeps the states it made (default build/sofa-head-states)')
    p.add_argument('--out', default=None, help='the table (default docs/sofa-examples.md; with --check: none)')
    p.add_argument('--timeout', type=float, default=20.0, help='seconds per penalty command (default 20)')
    p.add_argument('--jobs', type=int, default=2, help='scenes at a time (default 2)')
    p.add_argument('--expected', default=os.path.join(REPO, 'tests', 'sofa_examples_expected.txt'))
    p.add_argument('--check', action='store_true', help='fail when a scene of the expected list does not run')
    p.add_argument('--write-expected', action='store_true', help='rewrite the expected list with the scenes that run')
    p.add_argument('--py-examples', action='append', default=None,
                   help="folders of SOFA's Python example scripts (default ../sp3-src/examples and "
                        "../sofa-src/examples where they exist)")
    args = p.parse_args()
    for key in ('folder', 'penalty', 'states', 'sofa_head', 'made_states', 'out', 'expected'):
        if getattr(args, key):
            setattr(args, key, os.path.abspath(getattr(args, key)))
    args.data_dirs = args.data_dirs and [os.path.abspath(d) for d in args.data_dirs]
    args.py_examples = args.py_examples and [os.path.abspath(d) for d in args.py_examples]
    if args.py_examples is None:
        args.py_examples = [os.path.join(REPO, '..', 'sp3-src', 'examples'),
                            os.path.join(REPO, '..', 'sofa-src', 'examples')]
    args.folder = os.path.normpath(args.folder)
    if not os.path.isdir(args.folder):
        print(f'sofa-examples: no folder {args.folder}', file=sys.stderr)
        return 2
    if not os.access(args.penalty, os.X_OK):
        print(f'sofa-examples: no penalty executable {args.penalty}', file=sys.stderr)
        return 2
    if args.data_dirs is None:
        args.data_dirs = [os.path.dirname(args.folder), args.folder]
    if args.states is None:
        args.states = os.path.join(os.path.dirname(args.folder), 'examples-states')
    out = args.out if args.out is not None else (None if args.check else os.path.join(REPO, 'docs', 'sofa-examples.md'))

    args.components = registry(args)
    scenes = sorted(os.path.join(d, f) for d, _, files in os.walk(args.folder) for f in files if f.endswith('.scn'))
    start = time.monotonic()
    if args.sofa_head:
        # SOFA HEAD unpacks itself at its first start: once here, before the scenes run two at a
        # time (a second start during the unpack finds the binary before its libraries, exit 127)
        run([args.sofa_head], 10 * args.timeout)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        rows = list(pool.map(lambda s: check_scene(args, s), scenes))
    elapsed = time.monotonic() - start
    builds, runs = sum(r['builds'] for r in rows), sum(r['runs'] for r in rows)
    matches = sum(r['sofa'].startswith('yes') for r in rows)
    print(f'sofa-examples: builds {builds} / runs {runs} of {len(rows)}; matches SOFA {matches}; {elapsed:.0f} s')
    if out:
        unknown = unknown_components(args, set().union(*(r['uses'] for r in rows)))
        write_table(args, rows, unknown, out)
        print(f'sofa-examples: table {rel(out)}')

    running = {r['scene'] for r in rows if r['runs']}
    if args.write_expected:
        with open(args.expected, 'w') as f:
            f.write('# SOFA example scenes (relative to ../shared/sofa/examples) that `penalty run --steps 100` runs;\n'
                    '# scripts/sofa-examples.py --check fails when one stops running. Names only: SOFA\'s files are\n'
                    '# never committed. Regenerate with scripts/sofa-examples.py --write-expected.\n')
            for name in sorted(running):
                f.write(name + '\n')
        print(f'sofa-examples: expected list {rel(args.expected)} ({len(running)} scenes)')
    if args.check:
        with open(args.expected) as f:
            expected = [l.strip() for l in f if l.strip() and not l.startswith('#')]
        by_name = {r['scene']: r for r in rows}
        lost = [n for n in expected if n not in running]
        for n in lost:
            r = by_name.get(n)
            why = 'not found in the folder' if r is None else (r['blocker'] + ': ' + r['reason']).strip(': ')
            print(f'sofa-examples: FAIL {n} no longer runs: {why}', file=sys.stderr)
        if lost:
            return 1
        print(f'sofa-examples: all {len(expected)} expected scenes run')
    return 0


if __name__ == '__main__':
    sys.exit(main())
