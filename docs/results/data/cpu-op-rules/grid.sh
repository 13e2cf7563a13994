cd "$(git rev-parse --show-toplevel)"
for t in 0 0.1 0.25 0.5; do for e in 0.5 0.6 0.7; do
  d=runs/op-rule/t$t-e$e
  [ -f $d/summary.json ] || yokai eval runs/cpu-op/seed-0 runs/cpu-op/seed-1 runs/cpu-op/seed-2 --games 5000 --threads 2 --temperature $t --end $e -o $d > /dev/null 2>&1
  python3 -c "
import json,sys;g=json.load(open('$d/summary.json'))['groups'][0]
f=lambda m:'%.2f ± %.2f'%(m['mean'],m['se'])
print('T=$t END>$e', 'SP', f(g['sp']['reward']), 'XP', f(g['xp']['reward']), 'XP SEE %.1f'%g['xp']['see']['mean'], 'LEN %.1f'%g['xp']['length']['mean'])"
done; done
