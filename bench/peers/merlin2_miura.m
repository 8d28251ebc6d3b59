% merlin2_miura.m - the Miura sheet of bench/miura-study.sh M load on
% MERLIN2's bar-and-hinge model (N4B5), loaded along the same path:
% gravity and the tip load scaled by one load factor from 0 to PEND in
% NINC equal increments (below).
% Written for bench/peers/merlin2.sh, which sets M, NINC, PEND and the
% path of MERLIN2's sources (MERLIN2DIR) and reads the line it prints:
%   MERLIN2 m increments newton lambda tip_uz cpu_s
% The geometry and loads are smoothfold's: vertex (i, j), i, j = 0..2M,
% at x = i a + (j odd ? c : 0), y = j b; panels the parallelograms; the
% face at the origin held (its four corners fixed); the fold hinges get
% smoothfold's bending stiffness per length D / w (D = E t^3 / 12 (1 -
% nu^2) of the fold material, w the fold width), the panels a bending
% stiffness 100 times larger and stiff bars (smoothfold's faces are
% rigid); gravity as nodal forces (each panel's and fold band's weight
% shared by its corners), the tip load on the far corner.
addpath(MERLIN2DIR);
more off;
a = 0.02; b = 0.02; c = 0.008; w = 0.001;
E = 15.2e6; nu = 0.45; tf = 5.0e-4; rhof = 1200; tface = 1.0e-3; rhoface = 1040;
N = 2 * M;
[I, J] = meshgrid(0:N, 0:N);          % node k = j + (N + 1) i + 1
X = I * a + mod(J, 2) * c; Y = J * b;
Node = [X(:), Y(:), zeros(numel(X), 1)];
id = @(i, j) j + (N + 1) * i + 1;
Panel = cell(N * N, 1); k = 0;
for i = 0:N-1, for j = 0:N-1
    k = k + 1; Panel{k} = [id(i, j), id(i+1, j), id(i+1, j+1), id(i, j+1)];
end, end
% gravity: panel weight to its corners, fold band weight to its ends
g = 9.81; F = zeros(size(Node, 1), 1);
for k = 1:numel(Panel)
    P = Node(Panel{k}, 1:2);
    A = 0.5 * abs(sum(P(:,1) .* P([2:end 1],2) - P([2:end 1],1) .* P(:,2)));
    F(Panel{k}) = F(Panel{k}) - rhoface * tface * A * g / 4;
end
for i = 0:N, for j = 0:N
    if j < N && i > 0 && i < N   % zigzag crease (i, j)-(i, j+1)
        L = norm(Node(id(i, j+1), 1:2) - Node(id(i, j), 1:2));
        F([id(i, j), id(i, j+1)]) -= rhof * tf * w * L * g / 2;
    end
    if i < N && j > 0 && j < N   % straight crease (i, j)-(i+1, j)
        F([id(i, j), id(i+1, j)]) -= rhof * tf * w * a * g / 2;
    end
end, end
tip = id(N, N); F(tip) = F(tip) - 0.002;
% MERLIN2's geometric tests have absolute thresholds (its hinge sign test
% at 1e-8 on a product of three lengths, Newton's 1e-6 on the step) made
% for sheets of unit size: in metres (a = 0.02) its Newton stalls from
% the first increment.  Lengths are therefore in units of a: forces,
% stiffnesses per length (N) and bar forces keep their numbers, moments
% and displacements are those in metres times 1 / a.
Node = Node / a;
Load = [(1:size(Node, 1))', zeros(size(Node, 1), 2), F];
Supp = [id(0, 0), 1, 1, 1; id(1, 0), 1, 1, 1; id(1, 1), 1, 1, 1; id(0, 1), 1, 1, 1];
D = E * tf^3 / (12 * (1 - nu^2));
opt = struct('ModelType', 'N4B5', 'MaterCalib', 'manual', ...
    'BarCM', @(Ex) Ogden(Ex, 1e7), 'Abar', 1e-4, ...
    'Kb', 100 * D / w, 'Kf', D / w, ...
    'RotSprBend', @(he, h0, kb, L0) EnhancedLinear(he, h0, kb, L0, 30, 330), ...
    'RotSprFold', @(he, h0, kf, L0) EnhancedLinear(he, h0, kf, L0, 30, 330), ...
    'LoadType', 'Force');
[truss, angles, opt] = PrepareData(Node, Panel, Supp, Load, opt);
% Equal increments of the load factor, lambda_k = k PEND / NINC, each
% solved by Newton on MERLIN2's internal forces and tangent stiffness
% (GlobalK_fast_ver) with a sparse direct solve, to MERLIN2's own test
% (|dU| < 1e-6 over the free degrees of freedom).  MERLIN2's PathAnalysis
% would grow its increments where Newton converges fast (its modified
% generalised displacement control), so it is not used: the increments
% are the same as smoothfold's in number and range.
n3 = 3 * size(truss.Node, 1);
free = setdiff(1:n3, truss.FixedDofs);
U = zeros(n3, 1); Fv = opt.Load; newton = 0; done = 0; lam = 0;
t0 = cputime;
for k = 1:NINC
    lk = k * PEND / NINC; ok = 0;
    for it = 1:50
        [IF, K] = GlobalK_fast_ver(U, truss.Node, truss, angles);
        R = lk * Fv - IF;
        dU = K(free, free) \ R(free);
        U(free) = U(free) + dU;
        newton = newton + 1;
        if norm(dU) < 1e-6, ok = 1; break; end
    end
    if ~ok, break; end
    done = k; lam = lk;
end
t = cputime - t0;
printf('MERLIN2 %d %d %d %.6g %.6g %.3f\n', M, done, newton, lam, a * U(3 * tip), t);
