import matplotlib.pyplot as plt
import numpy as np

import kinetic_fem as kf

dist = kf.solve_heated(0.6)  # heated steady state at alpha = 0.6, n = D = 1 (FEM)
print(f"{dist.method}: converged={dist.info.converged}, {dist.v.size} nodes")
print(f"T = {dist.temperature:.6f}, a2 = {dist.a2:.6f}, f(0) = {dist.f(0.0):.6f}")
print(f"first-order Sonine theory: a2 = {kf.sonine.a2_first_order(0.6):.6f}")
print(f"f(c) at c = 4, 8, 12: {dist.f([4.0, 8.0, 12.0])}")

c = np.linspace(0.0, 12.0, 300)
plt.semilogy(c, dist.f(c), label="FEM, alpha = 0.6")
plt.semilogy(c, np.exp(-c**2 / 2) / np.sqrt(2 * np.pi), "k--", label="Gaussian")
plt.xlabel("c = v / sqrt(T)")
plt.ylabel("f(c)")
plt.legend()
plt.show()
