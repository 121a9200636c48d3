#!/usr/bin/env python3
"""scripts/sofa-examples.py on a folder of project-made scenes: the table's counts and columns
(builds, runs, contacts, matches SOFA against states penalty itself wrote, first blocker) and
--check's exit code naming a scene of the expected list that does not run.
usage: sofa_examples_script.py PENALTY_EXE REPO_DIR WORK_DIR"""
import os
import shutil
import subprocess
import sys

penalty, repo, work = (os.path.abspath(a) for a in sys.argv[1:4])
script = os.path.join(repo, 'scripts', 'sofa-examples.py')
shutil.rmtree(work, ignore_errors=True)
examples = os.path.join(work, 'examples')
os.makedirs(os.path.join(examples, 'Demo'))
shutil.copy(os.path.join(repo, 'tests', 'cli', 'cube_on_floor.scn'), os.path.join(examples, 'Demo', 'cube.scn'))
shutil.copy(os.path.join(repo, 'tests', 'cli', 'unknown_component.scn'), os.path.join(examples, 'unknown.scn'))
with open(os.path.join(examples, 'include.scn'), 'w') as f:  # an include whose root is spliced in (Group)
    f.write('<Node name="root">\n  <include href="Objects/Group.xml" totalMass="2"/>\n</Node>\n')
os.makedirs(os.path.join(examples, 'Objects'))
with open(os.path.join(examples, 'Objects', 'Group.xml'), 'w') as f:
    f.write('<Node name="Group">\n  <MechanicalObject position="0 0 0"/>\n  <UniformMass totalMass="1"/>\n'
            '  <GhostForceField/>\n</Node>\n')
# SOFA's states of the running scene: penalty's own (after init and after 100 steps), so it matches
states = os.path.join(work, 'examples-states', 'Demo', 'cube')
subprocess.run([penalty, 'run', os.path.join(examples, 'Demo', 'cube.scn'), '--steps', '101', '--quiet',
                '--export-states', states, '--export-every', '100'], check=True, capture_output=True)

# ... and the same scene against states moved by 1e-3 per value after 100 steps:
# SOFA's criterion 8 DOFs x 3 values x 1e-3 / 8 DOFs = 3e-3 > 1e-4, no match
shutil.copy(os.path.join(examples, 'Demo', 'cube.scn'), os.path.join(examples, 'Demo', 'moved.scn'))
moved = os.path.join(work, 'examples-states', 'Demo', 'moved')
shutil.copytree(states, moved)
for name in os.listdir(moved):
    lines = open(os.path.join(moved, name)).read().splitlines()
    x = [i for i, l in enumerate(lines) if l.split()[:1] == ['X=']][-1]
    lines[x] = '  X= ' + ' '.join(repr(float(v) + 1e-3) for v in lines[x].split()[1:])
    open(os.path.join(moved, name), 'w').write('\n'.join(lines) + '\n')

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)


expected = os.path.join(work, 'expected.txt')
with open(expected, 'w') as f:
    f.write('# comment\nDemo/cube.scn\nDemo/moved.scn\n')
table = os.path.join(work, 'table.md')
r = subprocess.run([sys.executable, script, examples, '--penalty', penalty, '--out', table, '--check',
                    '--expected', expected, '--jobs', '1'], capture_output=True, text=True)
check(r.returncode == 0, f'--check with a running scene: exit {r.returncode}: {r.stderr}')
check('builds 2 / runs 2 of 4' in r.stdout, f'summary line: {r.stdout}')
text = open(table).read()
check('**builds 2 / runs 2 of 4**; matches SOFA 1 of the 2 scenes with SOFA states' in text, 'table counts')
row = next((l for l in text.splitlines() if l.startswith('| Demo/cube.scn |')), '')
check(row.startswith('| Demo/cube.scn | yes | yes |') and '| yes (0) |' in row, f'running row: {row}')
row = next((l for l in text.splitlines() if l.startswith('| Demo/moved.scn |')), '')
check(row.startswith('| Demo/moved.scn | yes | yes |') and '| no (0.003) |' in row, f'moved row: {row}')
check('| unknown.scn | no | no |  |  | no reference | `FancyForceField` |' in text, 'unknown-component row')
check('| include.scn | no | no |  |  | no reference | `GhostForceField` |' in text, 'included unknown component row')
check('| `FancyForceField` | 1 | 1 | unknown (1) |' in text, 'blocker ranking row')
check('| `GhostForceField` | 1 | 1 |' in text, 'unknown components row (read through the include)')

with open(expected, 'a') as f:
    f.write('unknown.scn\n')
r = subprocess.run([sys.executable, script, examples, '--penalty', penalty, '--check', '--expected', expected,
                    '--jobs', '1'], capture_output=True, text=True)
check(r.returncode == 1, f'--check with a failing scene: exit {r.returncode}')
check("FAIL unknown.scn no longer runs: FancyForceField" in r.stderr, f'--check message: {r.stderr}')

# --sofa-head: SOFA HEAD's states made for the scenes without shared ones. A fake SOFA HEAD writes
# penalty's states and logs what SOFA HEAD logs for a component it does not create: a scene whose
# only such components are old names SOFA HEAD no longer knows at all (BoxConstraint: both drop
# it) is compared with those states; one with another such component has no reference.
head_examples = os.path.join(work, 'head-examples')
os.makedirs(head_examples)
cube_text = open(os.path.join(repo, 'tests', 'cli', 'cube_on_floor.scn')).read()
first_node = cube_text.index('<Node', cube_text.index('<Node') + 1)
for name, extra in (('dropped', '<BoxConstraint box="0 0 0 1 1 1"/>\n'), ('refused', '')):
    with open(os.path.join(head_examples, name + '.scn'), 'w') as f:
        f.write(cube_text[:first_node] + extra + cube_text[first_node:])
fake_head = os.path.join(work, 'fake-sofa-head')
with open(fake_head, 'w') as f:
    f.write(f"""#!{sys.executable}
import os, subprocess, sys
scene, steps, out = sys.argv[1:4]
kind = 'BoxConstraint' if 'dropped' in scene else 'FancyThing'
print(f'[ERROR]   [InfoComponent(Not created ({{kind}}))] Object type {{kind}}<> was not created')
print('[ERROR]   [SceneLoaderXML] Node initialization failed.')
subprocess.run([{penalty!r}, 'run', scene, '--steps', str(int(steps) + 1), '--quiet', '--export-states', out,
                '--export-every', steps], check=True, capture_output=True)
open('exported.vtk', 'w').write('a MeshExporter writes into the folder SOFA runs in')
""")
os.chmod(fake_head, 0o755)
made = os.path.join(work, 'made-states')
table = os.path.join(work, 'head-table.md')
r = subprocess.run([sys.executable, script, head_examples, '--penalty', penalty, '--out', table, '--sofa-head', fake_head,
                    '--made-states', made, '--jobs', '1'], capture_output=True, text=True, cwd=work)
check(r.returncode == 0, f'--sofa-head: exit {r.returncode}: {r.stderr}')
check(not os.path.exists(os.path.join(work, 'exported.vtk')),
      "a scene's exported file written into the folder the script runs in (not its scratch folder)")
text = open(table).read() if os.path.isfile(table) else ''
row = next((l for l in text.splitlines() if l.startswith('| dropped.scn |')), '')
check(row.startswith('| dropped.scn | yes | yes |') and '| yes (0) |' in row, f'a component both drop: {row}')
row = next((l for l in text.splitlines() if l.startswith('| refused.scn |')), '')
check('| no reference (SOFA HEAD does not create FancyThing) |' in row, f'a component SOFA HEAD refuses: {row}')
check(os.path.isfile(os.path.join(made, 'refused.refused')) and os.path.isdir(os.path.join(made, 'dropped')),
      'made states kept: the refusal and the states')

for f in failures:
    print('FAIL:', f)
if failures:
    sys.exit(1)
print('sofa-examples script checks passed')
