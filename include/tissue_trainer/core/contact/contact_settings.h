#pragma once
// Instrument-tissue contact settings (scene key `contact`, read by the scene loader), used by
// the contact library (tissue_trainer_contact). Plain numbers only: the scene knows nothing of
// Bullet.
namespace tt {

struct ContactSettings {
  double stiffness = 200.0;        // penalty k_c per contact point (N/m)
  // > 0: a contact per unit area instead, k_A times the area of the surface inside the tool
  // (N/m^3), sampled every sampleSpacing (m; 0: a quarter of the thinnest tool shape, at most 1 mm)
  double stiffnessPerArea = 0.0;
  double sampleSpacing = 0.0;
  double damping = 0.0;            // normal damping per contact point (N s/m; N s/m^3 with k_A)
  double graspStiffness = 100.0;   // spring from each grasped node to the tip (N/m)
  double graspJawAngle = 0.1;      // jaw opening (rad) below which the jaws grasp
  double graspRadius = 0.006;      // nodes within this distance of the jaw centre are grasped (m)
  int graspMaxNodes = 12;          // at most this many (the nearest) nodes per grasp
  // The stiffness K sent with f0 to the haptic side: the penalties' alone (the tissue held
  // fixed), or each penalty in series with the tissue's stiffness at its contact point, so the
  // felt stiffness follows the tissue's (a stiffening, beating wall feels stiffer at systole).
  bool tissueInSeries = false;
  // The tool the contact sees is a proxy that follows the device's tip at most this fast in
  // simulated time (m/s), so a frame that comes late never finds the tool far inside the
  // tissue; see tool_proxy.h. 0.1 m/s: above the fastest motion of the shipped task scripts
  // (0.087 m/s) and 1 cm in the longest frame of the simulation node's default (0.1 s).
  double toolMaxSpeed = 0.1;
};

}  // namespace tt
