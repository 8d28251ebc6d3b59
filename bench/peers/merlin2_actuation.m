% merlin2_actuation.m - a bending-face study on MERLIN2's bar-and-hinge
% model, folded by actuation: every crease's rest angle goes from flat to
% its value at p = 1 in NINC equal increments of p up to PEND.
% Written for bench/peers/merlin2_bending.sh, which sets MERLIN2DIR, DATA
% (the sheet: bench/peers/merlin2_sheet.py data), NINC, PEND, OUT and
% optionally EA (the bars' axial stiffness, N), and
% reads OUT:
%   node x y z          final position of every vertex [m]
%   hinge a b theta     final fold angle of hinge a-b [rad], valley > 0
%   MERLIN2 increments newton p max_bar_strain cpu_s
% The panels are smoothfold's rigid triangles, so MERLIN2 builds no
% bending hinge of its own: every interior edge is one of its fold hinges
% (creases and facet hinges alike), each with smoothfold's total
% stiffness K (the data's H) as MERLIN2's spring l k with k = K / l.
% Bars have EA (default 1e8 N; the table prints the largest strain):
% smoothfold's triangles are rigid, MERLIN2's stretch.
addpath(MERLIN2DIR);
more off;
source(DATA);
if ~exist('EA', 'var'), EA = 1e8; end
% MERLIN2's geometric thresholds are absolute (1e-8 in its hinge sign
% test, 1e-6 on Newton's step) and made for sheets of unit size, so
% lengths are in units of the sheet size Ls: forces keep their numbers,
% moments and energies scale by 1 / Ls, and k = K / l stays as it is.
n = size(XY, 1);
Node = [XY / Ls, zeros(n, 1)];
Panel = num2cell(Tri, 2);
Supp = [Fixed(:), ones(numel(Fixed), 3)];
opt = struct('ModelType', 'N4B5', 'MaterCalib', 'manual', ...
    'BarCM', @(Ex) Ogden(Ex, EA), 'Abar', 1, 'Kb', 1, 'Kf', 1, ...
    'RotSprBend', @(he, h0, kb, L0) EnhancedLinear(he, h0, kb, L0, 30, 330), ...
    'RotSprFold', @(he, h0, kf, L0) EnhancedLinear(he, h0, kf, L0, 30, 330), ...
    'LoadType', 'Force');
[truss, angles, opt] = PrepareData(Node, Panel, Supp, [], opt);
if ~isempty(angles.bend)
    error('merlin2_actuation: MERLIN2 split a triangle (%d bending hinges)', size(angles.bend, 1));
end
% Match MERLIN2's hinges to the data's by their end vertices.
nh = size(angles.fold, 1);
if nh ~= size(H, 1)
    error('merlin2_actuation: MERLIN2 has %d hinges, smoothfold %d', nh, size(H, 1));
end
row = zeros(nh, 1);
for h = 1:nh
    e = sort(angles.fold(h, 1:2));
    k = find(all(sort(H(:, 1:2), 2) == e, 2));
    if numel(k) ~= 1, error('merlin2_actuation: hinge %d-%d not in the data', e(1), e(2)); end
    row(h) = k;
end
% Valley (FOLD's sign, > 0) is the sense in which MERLIN2's angle moves
% when both wings rise above the sheet.
sv = zeros(nh, 1);
for h = 1:nh
    up = Node; f = angles.fold(h, :);
    up(f(3), 3) = up(f(3), 3) + 1e-3; up(f(4), 3) = up(f(4), 3) + 1e-3;
    sv(h) = sign(FoldKe(up, f) - pi);
end
angles.Kf = H(row, 4) ./ H(row, 5);
rest = H(row, 6);
n3 = 3 * n;
free = setdiff(1:n3, truss.FixedDofs);
U = zeros(n3, 1); newton = 0; done = 0; lam = 0;
t0 = cputime;
for k = 1:NINC
    lk = k * PEND / NINC; ok = 0;
    angles.pf0 = pi + sv .* rest * lk;
    for it = 1:50
        [IF, K] = GlobalK_fast_ver(U, truss.Node, truss, angles);
        dU = K(free, free) \ (-IF(free));
        U(free) = U(free) + dU;
        newton = newton + 1;
        if norm(dU) < 1e-6, ok = 1; break; end   % MERLIN2's own test
    end
    if ~ok, break; end
    done = k; lam = lk;
end
t = cputime - t0;
X = (truss.Node + reshape(U, 3, [])') * Ls;
eDof = kron(truss.Bars, 3 * ones(1, 3)) + repmat([-2, -1, 0], size(truss.Bars, 1), 2);
du = U(eDof(:, 1:3)) - U(eDof(:, 4:6));
strain = max(abs(truss.B * U ./ truss.L + 0.5 * sum(du .^ 2, 2) ./ truss.L .^ 2));
fid = fopen(OUT, 'w');
for i = 1:n, fprintf(fid, 'node %.12g %.12g %.12g\n', X(i, 1), X(i, 2), X(i, 3)); end
for h = 1:nh
    he = FoldKe(X / Ls, angles.fold(h, :));
    fprintf(fid, 'hinge %d %d %.12g\n', angles.fold(h, 1), angles.fold(h, 2), sv(h) * (he - pi));
end
fprintf(fid, 'MERLIN2 %d %d %.6g %.3g %.3f\n', done, newton, lam, strain, t);
fclose(fid);
